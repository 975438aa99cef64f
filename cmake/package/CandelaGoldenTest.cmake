# Golden-image tests for projects that use Candela (included by CandelaConfig.cmake).
#
# candela_add_golden_test(NAME SCENE GOLDEN [SIZE WxH] [OPTIONS arg...] [TOLERANCE DIFF [FRACTION]]
#                         [NO_UPDATE])
#
# Adds the ctest test NAME (label "golden"): Candela::candela renders SCENE offscreen
# (`candela render --backend auto`: EGL, else OSMesa; GL debug output on, so a GL error fails it;
# --verify-state) at SIZE (default 256x256, as Candela's own goldens) with OPTIONS (any
# `candela render` options, e.g. --effects, --set, --camera; given last, so they override), then
# `candela compare` checks the image against GOLDEN. The tolerance is Candela's own goldens': a
# pixel fails when a channel differs by more than DIFF (default 2/255) and the test fails when more
# than FRACTION of the pixels fail (default 0.001), or on any non-finite value. On failure the
# candidate and a heat map of the difference are left in <build dir>/candela-golden/ as
# NAME.candidate.png and NAME.diff.png, and the test prints both paths. Relative SCENE and GOLDEN
# are taken from the current source directory. Exit 3 of the render (no usable OpenGL) fails the
# test and says so.
#
# The target update-goldens re-renders every golden of the project (each test's command with the
# image written to GOLDEN); NO_UPDATE leaves a test out of it (a test that must fail, or one that
# shares its GOLDEN with another: a golden is rewritten by the first test that names it).

set(_CANDELA_GOLDEN_SCRIPT "${CMAKE_CURRENT_LIST_DIR}/candela_golden_check.cmake")

function(candela_add_golden_test name scene golden)
  cmake_parse_arguments(PARSE_ARGV 3 ARG "NO_UPDATE" "SIZE" "OPTIONS;TOLERANCE")
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "candela_add_golden_test(${name}): unexpected arguments '${ARG_UNPARSED_ARGUMENTS}' "
                        "(expected NAME SCENE GOLDEN [SIZE WxH] [OPTIONS ...] [TOLERANCE DIFF [FRACTION]] [NO_UPDATE])")
  endif()
  if(NOT TARGET Candela::candela)
    message(FATAL_ERROR "candela_add_golden_test(${name}): Candela::candela is not defined (find_package(Candela) first)")
  endif()
  set(size 256x256)
  if(DEFINED ARG_SIZE)
    if(NOT ARG_SIZE MATCHES "^[1-9][0-9]*x[1-9][0-9]*$")
      message(FATAL_ERROR "candela_add_golden_test(${name}): SIZE '${ARG_SIZE}' must be WxH (e.g. 128x96)")
    endif()
    set(size ${ARG_SIZE})
  endif()
  set(diff "")
  set(fraction "")
  if(DEFINED ARG_TOLERANCE)
    list(LENGTH ARG_TOLERANCE n)
    if(n GREATER 2)
      message(FATAL_ERROR "candela_add_golden_test(${name}): TOLERANCE takes DIFF and optionally FRACTION")
    endif()
    foreach(value IN LISTS ARG_TOLERANCE)
      if(NOT value MATCHES "^([0-9]+\\.?[0-9]*|\\.[0-9]+)([eE][-+]?[0-9]+)?$")
        message(FATAL_ERROR "candela_add_golden_test(${name}): TOLERANCE '${value}' is not a non-negative number")
      endif()
    endforeach()
    list(GET ARG_TOLERANCE 0 diff)
    if(n EQUAL 2)
      list(GET ARG_TOLERANCE 1 fraction)
    endif()
  endif()
  get_filename_component(scene "${scene}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  get_filename_component(golden "${golden}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  # The output files are named after the test; characters a file name should not carry become _.
  string(REGEX REPLACE "[^A-Za-z0-9_.+-]" "_" file_name "${name}")
  set(out_dir "${CMAKE_CURRENT_BINARY_DIR}/candela-golden")
  # The arguments are written out in both commands below (not kept in a list variable): OPTIONS is a
  # list, and only a quoted argument keeps its semicolons for the script.
  add_test(NAME ${name}
           COMMAND ${CMAKE_COMMAND} -DCANDELA=$<TARGET_FILE:Candela::candela> "-DNAME=${file_name}" "-DSCENE=${scene}"
                   "-DGOLDEN=${golden}" "-DOUT_DIR=${out_dir}" "-DSIZE=${size}" "-DOPTIONS=${ARG_OPTIONS}"
                   "-DTOLERANCE=${diff}" "-DMAX_FAILING=${fraction}" -P "${_CANDELA_GOLDEN_SCRIPT}")
  set_tests_properties(${name} PROPERTIES LABELS golden)

  if(NOT ARG_NO_UPDATE)
    get_property(updated GLOBAL PROPERTY CANDELA_GOLDENS_UPDATED)
    if(golden IN_LIST updated)
      return()  # rewritten by the first test that names it
    endif()
    set_property(GLOBAL APPEND PROPERTY CANDELA_GOLDENS_UPDATED "${golden}")
    if(NOT TARGET update-goldens)
      add_custom_target(update-goldens COMMENT "Re-rendered every candela_add_golden_test golden; commit them with the reason")
    endif()
    add_custom_target(update-golden-${file_name}
                      COMMAND ${CMAKE_COMMAND} -DCANDELA=$<TARGET_FILE:Candela::candela> "-DNAME=${file_name}"
                              "-DSCENE=${scene}" "-DGOLDEN=${golden}" "-DOUT_DIR=${out_dir}" "-DSIZE=${size}"
                              "-DOPTIONS=${ARG_OPTIONS}" -DUPDATE=ON -P "${_CANDELA_GOLDEN_SCRIPT}"
                      COMMENT "Rendering ${golden}" VERBATIM)
    add_dependencies(update-goldens update-golden-${file_name})
  endif()
endfunction()
