# Runs COMMAND (a ;-list) and checks its exit code and that its stderr+stdout match REGEX.
#   cmake -DCOMMAND="a;b" -DEXPECT_EXIT=2 -DREGEX="..." [-DNOT_REGEX="..."] [-DENV="K=V;..."] [-DTIMEOUT=s] -P expect.cmake
if(ENV)
  foreach(kv IN LISTS ENV)
    string(REGEX MATCH "^([^=]+)=(.*)$" _ "${kv}")
    set(ENV{${CMAKE_MATCH_1}} "${CMAKE_MATCH_2}")
  endforeach()
endif()
if(NOT TIMEOUT)
  set(TIMEOUT 120)
endif()
# LeakSanitizer's stop-the-world tracer itself sometimes segfaults at exit while a driver thread
# is still being torn down ("Tracer caught signal 11 ... LeakSanitizer has encountered a fatal
# error", google/sanitizers#1353). That is the checker failing, not a leak and not Candela: the run
# is repeated (at most twice more) only on that exact signature. A real leak report, a crash of the
# program or a wrong exit code is never retried.
foreach(attempt RANGE 1 3)
  execute_process(COMMAND ${COMMAND} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT ${TIMEOUT})
  if("${code}" STREQUAL "${EXPECT_EXIT}" OR NOT "${err}" MATCHES "LeakSanitizer has encountered a fatal error"
     OR "${err}" MATCHES "ERROR: LeakSanitizer: detected memory leaks")
    break()
  endif()
  message("attempt ${attempt}: LeakSanitizer's tracer crashed (not a leak report)\n${err}")
endforeach()
message("exit code: ${code}\nstdout:\n${out}\nstderr:\n${err}")
if(NOT "${code}" STREQUAL "${EXPECT_EXIT}")
  message(FATAL_ERROR "expected exit code ${EXPECT_EXIT}, got ${code}")
endif()
if(REGEX AND NOT "${out}${err}" MATCHES "${REGEX}")
  message(FATAL_ERROR "output does not match: ${REGEX}")
endif()
# Every image the command wrote is checked for NaN/Inf (compare --check fails on non-finite).
list(FIND COMMAND "-o" _o)
if(_o GREATER -1 AND EXPECT_EXIT EQUAL 0)
  math(EXPR _i "${_o} + 1")
  list(GET COMMAND ${_i} _image)
  list(GET COMMAND 0 _candela)
  if(EXISTS "${_image}")
    execute_process(COMMAND ${_candela} compare ${_image} ${_image} --check RESULT_VARIABLE _c OUTPUT_VARIABLE _out)
    if(NOT _c EQUAL 0)
      message(FATAL_ERROR "${_image} has non-finite values:\n${_out}")
    endif()
    message("checked ${_image}: no non-finite values")
  endif()
endif()
if(NOT_REGEX AND "${out}${err}" MATCHES "${NOT_REGEX}")
  message(FATAL_ERROR "output matches what it must not: ${NOT_REGEX}")
endif()
