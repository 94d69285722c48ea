// DESIGN rule 2: the core headers compile as C++, as nvcc compiles them for
// the CUDA kernel (src/render/gpu.cu). Compiled, never linked or run, by
// tests/test_core_cxx.cmake (CTest: test_core_cxx) with the C++ compiler,
// -std=c++11 and -std=c++17, -pedantic-errors -Wall -Wextra -Werror: C-only
// constructs (VLAs, compound literals, designated initializers, bare
// restrict, <complex.h>, implicit void * conversions) fail here.
//
// core_headers.inc is written by that script when the test runs and includes
// every src/core/*.h, so a new core header is covered without editing this
// file. Each header is also compiled on its own there (self-contained).
#include "core_headers.inc"

// gpu.cu copies these between host and device: complete types in C++ too.
static_assert(sizeof(cr_pixel) > 0, "cr_pixel is a complete type in C++");
static_assert(sizeof(cr_frame) > 0, "cr_frame is a complete type in C++");
