# One golden-image check of candela_add_golden_test (CandelaGoldenTest.cmake), run by ctest:
#   cmake -DCANDELA=candela -DNAME=N -DSCENE=S.gltf -DGOLDEN=G.png -DOUT_DIR=D -DSIZE=WxH
#         [-DOPTIONS=arg;...] [-DTOLERANCE=DIFF] [-DMAX_FAILING=FRACTION] [-DUPDATE=ON]
#         -P candela_golden_check.cmake
# Renders S to D/N.candidate.png and compares it with G; on failure leaves the candidate and the
# heat map D/N.diff.png and prints their paths. UPDATE=ON (the update-goldens target) writes G.
cmake_minimum_required(VERSION 3.25)
foreach(var CANDELA NAME SCENE GOLDEN OUT_DIR SIZE)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "candela_golden_check.cmake: -D${var}=... is required")
  endif()
endforeach()
if(NOT EXISTS "${SCENE}")
  message(FATAL_ERROR "${NAME}: the scene ${SCENE} does not exist")
endif()

set(candidate "${OUT_DIR}/${NAME}.candidate.png")
set(diff "${OUT_DIR}/${NAME}.diff.png")
file(MAKE_DIRECTORY "${OUT_DIR}")
file(REMOVE "${candidate}" "${diff}")  # what is there after the run is this run's

# --backend auto: EGL, and OSMesa when EGL gives no usable context. CANDELA_DEBUG_GL=1: GL debug
# output on, a GL error is exit 1. OPTIONS come last: a repeated option overrides (--backend egl).
execute_process(COMMAND ${CMAKE_COMMAND} -E env CANDELA_DEBUG_GL=1
                        "${CANDELA}" render "${SCENE}" -o "${candidate}" --size ${SIZE} --backend auto --verify-state ${OPTIONS}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(rc EQUAL 3)
  message(FATAL_ERROR "FAIL ${NAME}: no usable OpenGL 4.5 (candela render exit 3): neither EGL nor OSMesa gave a context")
elseif(NOT rc EQUAL 0)
  message(FATAL_ERROR "FAIL ${NAME}: candela render exited with ${rc} (docs: 1 internal error or GL error, 2 bad input)")
endif()
if(err MATCHES "non-finite values")
  message(FATAL_ERROR "FAIL ${NAME}: the render has non-finite values (written as 0 in ${candidate})")
endif()
if(NOT EXISTS "${candidate}")
  message(FATAL_ERROR "FAIL ${NAME}: candela render exited 0 but wrote no ${candidate}")
endif()

if(UPDATE)
  get_filename_component(golden_dir "${GOLDEN}" DIRECTORY)
  file(MAKE_DIRECTORY "${golden_dir}")
  file(COPY_FILE "${candidate}" "${GOLDEN}")
  file(REMOVE "${candidate}")
  message("updated ${GOLDEN}")
  return()
endif()

if(NOT EXISTS "${GOLDEN}")
  message(FATAL_ERROR "FAIL ${NAME}: no golden ${GOLDEN}\n  candidate: ${candidate}\n"
                      "(`cmake --build <build dir> --target update-goldens` renders it; check it before committing)")
endif()
set(compare_args)
if(NOT "${TOLERANCE}" STREQUAL "")
  list(APPEND compare_args --tolerance ${TOLERANCE})
endif()
if(NOT "${MAX_FAILING}" STREQUAL "")
  list(APPEND compare_args --max-failing ${MAX_FAILING})
endif()
execute_process(COMMAND "${CANDELA}" compare "${candidate}" "${GOLDEN}" --check --heatmap "${diff}" ${compare_args}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(rc EQUAL 0)
  file(REMOVE "${candidate}" "${diff}")
  message("ok ${NAME}")
elseif(rc EQUAL 4)
  message(FATAL_ERROR "FAIL ${NAME}: beyond tolerance against ${GOLDEN}\n  candidate: ${candidate}\n  diff:      ${diff}")
else()
  # 2: the golden has another size than SIZE, or is no image; 1: e.g. no image I/O module.
  file(REMOVE "${diff}")
  message(FATAL_ERROR "FAIL ${NAME}: candela compare exited with ${rc}\n  candidate: ${candidate}")
endif()
