# DESIGN rule 2: compile every core header as C++ (syntax and semantics only,
# nothing is linked). Run by CTest as test_core_cxx:
#   cmake -DCXX=<C++ compiler> -DSRC=<repository>/src -DTU=<tests/test_core_cxx.cpp>
#         -DWORK=<scratch folder> -P tests/test_core_cxx.cmake
# Fails, printing the compiler's messages, when any header does not compile
# on its own or when all of them together do not.
foreach(v CXX SRC TU WORK)
  if(NOT ${v})
    message(FATAL_ERROR "test_core_cxx.cmake: -D${v}=... is missing")
  endif()
endforeach()

file(GLOB headers RELATIVE "${SRC}" "${SRC}/core/*.h")
list(SORT headers)
if(NOT headers)
  message(FATAL_ERROR "test_core_cxx: no headers in ${SRC}/core")
endif()
set(inc "// written by tests/test_core_cxx.cmake: every src/core/*.h\n")
foreach(h IN LISTS headers)
  string(APPEND inc "#include \"${h}\"\n")
endforeach()
file(MAKE_DIRECTORY "${WORK}")
file(WRITE "${WORK}/core_headers.inc" "${inc}")

set(flags -fsyntax-only -pedantic-errors -Wall -Wextra -Werror -D_POSIX_C_SOURCE=200809L
    "-I${SRC}" "-I${WORK}")
set(failed "")

function(cr_cxx_compile label)
  execute_process(COMMAND "${CXX}" ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE out)
  if(rc EQUAL 0)
    message("ok      ${label}")
  else()
    message("FAILED  ${label}\n${out}")
    set(failed "${failed} ${label}" PARENT_SCOPE)
  endif()
endfunction()

foreach(h IN LISTS headers)
  cr_cxx_compile("${h} alone, -std=c++11" -std=c++11 ${flags} -x c++ "${SRC}/${h}")
endforeach()
foreach(std c++11 c++17)
  cr_cxx_compile("all core headers, -std=${std}" -std=${std} ${flags} "${TU}")
endforeach()

list(LENGTH headers n)
if(failed)
  message(FATAL_ERROR "test_core_cxx: does not compile as C++:${failed}")
endif()
message("test_core_cxx: ${n} core headers compile as C++ (${CXX})")
