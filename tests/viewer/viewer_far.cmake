# The viewer far from the origin: one fly-through script (tests/viewer/flythrough.script) run on
# a scene at the origin and on the same scene with its roots 6.1e6 m away (on the Earth's surface,
# as geospatial glTF places it). Every screenshot of the far run must equal the origin run's at
# the golden tolerance: a moving camera does not make the far scene swim or shake. GI is left
# out on both: its probes turn float rounding into differences of their own (docs/design.md).
#   cmake -DCANDELA=... -DNEAR=... -DFAR=... -DSCRIPT=... -DOUT=... -P viewer_far.cmake
include(${CMAKE_CURRENT_LIST_DIR}/../cmake/steps.cmake)
set(size 200x150)
foreach(where near far)
  set(dir ${OUT}/viewer_far/${where})
  file(REMOVE_RECURSE ${dir})
  file(MAKE_DIRECTORY ${dir})
  string(TOUPPER ${where} var)
  candela_view_or_fail(${dir} err ${${var}} --size ${size} --script ${SCRIPT} --effects shadows --no-vsync)
  string(REGEX MATCHALL "wrote fly_[0-9]\\.png[^\n]*, 0 non-finite radiance values" clean "${err}")
  list(LENGTH clean n_clean)
  if(NOT n_clean EQUAL 4)
    message(FATAL_ERROR "expected 4 screenshots with 0 non-finite radiance values in the ${where} run, the log has ${n_clean}")
  endif()
endforeach()
if(NOT err MATCHES "origin: \\(")
  message(FATAL_ERROR "the far run's log does not say where the scene's origin is")
endif()
foreach(k 1 2 3 4)
  candela_same_or_fail(${OUT}/viewer_far/far/fly_${k}.png ${OUT}/viewer_far/near/fly_${k}.png ${OUT}/viewer_far/fly_${k}_diff.png
                       "screenshot ${k} of the fly-through 6.1e6 m from the origin (against the same at the origin)")
endforeach()
# The moves change the picture: consecutive screenshots differ (else the test compares nothing).
foreach(pair "1;2" "2;3" "3;4")
  list(GET pair 0 a)
  list(GET pair 1 b)
  execute_process(COMMAND ${CANDELA} compare ${OUT}/viewer_far/near/fly_${a}.png ${OUT}/viewer_far/near/fly_${b}.png --check
                  RESULT_VARIABLE code OUTPUT_QUIET ERROR_QUIET)
  if(code EQUAL 0)
    message(FATAL_ERROR "screenshots ${a} and ${b} of the fly-through are the same image: the script did not move the camera")
  endif()
endforeach()
