# The version `candela --version` prints: PROJECT_VERSION (the top-level project() call) and the
# git commit the build was configured from. The commit is read at configure time only (a commit
# made since shows after the next configure); "unknown" when git is missing or the source tree is
# not the top of a git checkout (an unpacked tarball inside some other repository reports unknown,
# not that repository's commit). Only a short hash is kept: no path of the machine.
set(CANDELA_GIT_HASH "unknown")
find_package(Git QUIET)
if(GIT_FOUND)
  execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --show-toplevel WORKING_DIRECTORY ${CMAKE_SOURCE_DIR}
                  OUTPUT_VARIABLE _top RESULT_VARIABLE _rc OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(_rc EQUAL 0)
    file(REAL_PATH "${_top}" _top)
    file(REAL_PATH "${CMAKE_SOURCE_DIR}" _src)
    if(_top STREQUAL _src)
      execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --short=12 HEAD WORKING_DIRECTORY ${CMAKE_SOURCE_DIR}
                      OUTPUT_VARIABLE _hash RESULT_VARIABLE _rc OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
      if(_rc EQUAL 0 AND _hash MATCHES "^[0-9a-f]+$")
        set(CANDELA_GIT_HASH "${_hash}")
      endif()
    endif()
  endif()
endif()
configure_file(${CMAKE_CURRENT_LIST_DIR}/candela_version.hpp.in ${CMAKE_BINARY_DIR}/generated/candela_version.hpp @ONLY)
message(STATUS "Candela ${PROJECT_VERSION} (git ${CANDELA_GIT_HASH})")
