# WebAssembly build of src/core with the web entry point (src/wasm/web.c),
# for the browser explorer (web/), and its tests (tests/web).
#
# Toolchain: clang's wasm32-wasi target with wasi-libc (Debian: clang lld-14
# wasi-libc libclang-rt-14-dev-wasm32). Emscripten 3.1.6 (Debian: emscripten,
# with NODE_PATH=/usr/share/nodejs) builds the same source into the same image
# but brings a JavaScript runtime the page does not need, and was no faster
# (BENCHMARKS.md, "WebAssembly in the browser"). The module is a WASI reactor
# importing only three WASI functions, which the page stubs (stdio it never
# calls).
#
# Besides the core it compiles the command line's scene evaluation and pixel
# maps (CURRAY_WASM_HOST_SOURCES: cr_scene_frame, cr_redshift_color, ...), so
# the page checks scenes with the same messages and colours the maps the same
# way. Those files also hold the YAML and PNG readers; only libyaml's header
# is needed (a copy in the build folder, so no host header is seen), and
# --gc-sections drops every function the entry point does not reach, so
# neither library is linked.
option(CURRAY_WASM "Build the WebAssembly core (web/) when clang's wasm32-wasi target works" ON)
set(CURRAY_HAVE_WASM OFF)
set(CURRAY_WASM_HOST_SOURCES src/input/scene_parse.c src/input/scene_eval.c src/input/names.c
    src/input/settings.c src/base/error.c src/input/sysconfig.c src/output/output.c)
set(CURRAY_WASM_EXPORTS cr_web_new cr_web_free cr_web_set cr_web_set_word cr_web_sky
    cr_web_clear_spheres cr_web_add_sphere cr_web_frame cr_web_message cr_web_trace
    cr_web_probe cr_web_reproject cr_web_width cr_web_height malloc free)
if(CURRAY_WASM)
  find_program(CURRAY_WASM_CC NAMES clang clang-14)
  set(_cr_wasm_dir ${CMAKE_BINARY_DIR}/wasm-probe)
  file(MAKE_DIRECTORY ${_cr_wasm_dir})
  file(WRITE ${_cr_wasm_dir}/probe.c "#include <math.h>\n#include <stdio.h>\n#include <stdlib.h>\n"
       "int cr_probe(int n) { char b[32]; void *p = malloc(n); snprintf(b, sizeof b, \"%g\", sin(n));"
       " free(p); return b[0]; }\n")
  if(CURRAY_WASM_CC)
    execute_process(COMMAND ${CURRAY_WASM_CC} --target=wasm32-wasi -O2 -mexec-model=reactor
                            -Wl,--export=cr_probe ${_cr_wasm_dir}/probe.c -o ${_cr_wasm_dir}/probe.wasm
                    RESULT_VARIABLE _cr_wasm_rc OUTPUT_QUIET ERROR_VARIABLE _cr_wasm_err)
  else()
    set(_cr_wasm_rc 1)
    set(_cr_wasm_err "clang not found")
  endif()
  if(_cr_wasm_rc EQUAL 0)
    set(CURRAY_HAVE_WASM ON)
    message(STATUS "curray: clang's wasm32-wasi target works, building the WebAssembly core (web/)")
  else()
    string(REGEX REPLACE "\n.*" "" _cr_wasm_err "${_cr_wasm_err}")
    if(_cr_wasm_err STREQUAL "")
      set(_cr_wasm_err "${CURRAY_WASM_CC} --target=wasm32-wasi failed: ${_cr_wasm_rc}")
    endif()
    message(STATUS "curray: no working wasm32-wasi toolchain (${_cr_wasm_err}); Debian: clang "
                   "lld-14 wasi-libc libclang-rt-14-dev-wasm32. The WebAssembly core (web/) is "
                   "not built and its tests are skipped")
  endif()
endif()

# cr_wasm_link(OUTPUT file SOURCES src... [REACTOR]): one wasm32-wasi link of
# the given sources (relative to the source folder) with the core's flags.
function(cr_wasm_link)
  cmake_parse_arguments(W "REACTOR" "OUTPUT" "SOURCES" ${ARGN})
  # -O3 -msimd128: bench/web.sh measured -O2 at 1.8x the native CPU time a
  # ray, -O3 at 1.0-1.1x, -O3 with WebAssembly SIMD at 0.9-1.0x (BENCHMARKS.md);
  # -mnontrapping-fptoint (saturating float-to-int, in every browser since
  # 2019) takes 7 % off a look-around frame
  set(_flags --target=wasm32-wasi -O3 -msimd128 -mnontrapping-fptoint -std=c11 -D_POSIX_C_SOURCE=200809L
             -DCURRAY_VERSION="${PROJECT_VERSION}" -Wall -Wextra
             -ffunction-sections -fdata-sections -Wl,--gc-sections
             -isystem ${CMAKE_BINARY_DIR}/wasm-include -I${PROJECT_SOURCE_DIR}/src)
  if(W_REACTOR)
    list(APPEND _flags -mexec-model=reactor)
    foreach(_s IN LISTS CURRAY_WASM_EXPORTS)
      list(APPEND _flags -Wl,--export=${_s})
    endforeach()
  endif()
  set(_srcs "")
  foreach(_s IN LISTS W_SOURCES)
    list(APPEND _srcs ${PROJECT_SOURCE_DIR}/${_s})
  endforeach()
  file(GLOB _cr_headers ${PROJECT_SOURCE_DIR}/src/core/*.h ${PROJECT_SOURCE_DIR}/src/base/*.h
       ${PROJECT_SOURCE_DIR}/src/input/*.h ${PROJECT_SOURCE_DIR}/src/output/*.h
       ${PROJECT_SOURCE_DIR}/src/wasm/*.h)
  get_filename_component(_dir ${W_OUTPUT} DIRECTORY)
  add_custom_command(OUTPUT ${W_OUTPUT}
                     COMMAND ${CMAKE_COMMAND} -E make_directory ${_dir}
                     COMMAND ${CURRAY_WASM_CC} ${_flags} ${_srcs} -o ${W_OUTPUT}
                     DEPENDS ${_srcs} ${_cr_headers}
                     COMMENT "wasm32-wasi: ${W_OUTPUT}" VERBATIM)
endfunction()

if(CURRAY_HAVE_WASM)
  configure_file(${YAML_INCLUDE_DIR}/yaml.h ${CMAKE_BINARY_DIR}/wasm-include/yaml.h COPYONLY)
  set(CURRAY_WASM_CORE ${CMAKE_BINARY_DIR}/web/curray-core.wasm)
  cr_wasm_link(OUTPUT ${CURRAY_WASM_CORE} REACTOR
               SOURCES src/wasm/web.c ${CURRAY_WASM_HOST_SOURCES})
  # the page as one static folder, build/web (web/bundle.py)
  find_package(Python3 COMPONENTS Interpreter)
  if(Python3_Interpreter_FOUND)
    set(_cr_page index.html style.css core.js yaml.js app.js bundle.py)
    list(TRANSFORM _cr_page PREPEND ${PROJECT_SOURCE_DIR}/web/)
    set(_cr_tex ${PROJECT_SOURCE_DIR}/scenes/sky.png ${PROJECT_SOURCE_DIR}/scenes/sky_grid.png)
    set(CURRAY_WEB_DIR ${CMAKE_BINARY_DIR}/web)
    add_custom_command(OUTPUT ${CURRAY_WEB_DIR}/index.html ${CURRAY_WEB_DIR}/curray-core.js
                       COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/web/bundle.py
                               ${CURRAY_WEB_DIR} ${CURRAY_WASM_CORE} ${_cr_tex}
                       DEPENDS ${_cr_page} ${_cr_tex} ${CURRAY_WASM_CORE}
                       COMMENT "web: the browser explorer in ${CURRAY_WEB_DIR}" VERBATIM)
    add_custom_target(curray_wasm ALL DEPENDS ${CURRAY_WASM_CORE} ${CURRAY_WEB_DIR}/index.html)
  else()
    message(STATUS "curray: Python 3 not found: the page (build/web) is not assembled")
    add_custom_target(curray_wasm ALL DEPENDS ${CURRAY_WASM_CORE})
  endif()
endif()
