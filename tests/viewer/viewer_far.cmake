# The viewer far from the origin: one fly-through script (tests/viewer/flythrough.script) run on
# a scene at the origin and on the same scene with its roots 6.1e6 m away (on the Earth's surface,
# as geospatial glTF places it). Every screenshot of the far run must equal the origin run's at
# the golden tolerance: a moving camera does not make the far scene swim or shake. GI is left
# out on both: its probes turn float rounding into differences of their own (docs/design.md).
# Then a scene large compared with what the camera sees: two identical rooms 1e5 m apart
# (TWO_ROOMS, TWO_ROOMS_SCRIPT). The camera flies to the far room, moves in it and flies back: the
# viewer moves the scene's origin to the camera on landing, and each view of the far room equals
# the same view of the near one (without that move: 3.4 % of the pixels beyond 2/255).
#   cmake -DCANDELA=... -DNEAR=... -DFAR=... -DSCRIPT=... -DTWO_ROOMS=... -DTWO_ROOMS_SCRIPT=... -DOUT=... -P viewer_far.cmake
include(${CMAKE_CURRENT_LIST_DIR}/../cmake/steps.cmake)
set(size 200x150)
foreach(where near far)
  set(dir ${OUT}/viewer_far/${where})
  file(REMOVE_RECURSE ${dir})
  file(MAKE_DIRECTORY ${dir})
  string(TOUPPER ${where} var)
  candela_view_or_fail(${dir} err ${${var}} --size ${size} --script ${SCRIPT} --effects shadows --no-vsync)
  candela_clean_shots_or_fail("${err}" "fly_[0-9]\\.png" 4 "in the ${where} run")
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
# The two rooms.
set(dir ${OUT}/viewer_far/two_rooms)
file(REMOVE_RECURSE ${dir})
file(MAKE_DIRECTORY ${dir})
candela_view_or_fail(${dir} err ${TWO_ROOMS} --size ${size} --script ${TWO_ROOMS_SCRIPT} --effects shadows --no-vsync)
candela_log_says_or_fail("${err}" "the log"
    "frame 3: origin moved to the camera, \\(100000, 1, 3.39[0-9]+\\)"
    "frame 9: origin moved to the camera, \\(0.25, 0.87[0-9]+, 2.14[0-9]+\\)")
candela_clean_shots_or_fail("${err}" "rooms_[0-9]\\.png" 4 "in the two rooms")
candela_same_or_fail(${dir}/rooms_2.png ${dir}/rooms_1.png ${dir}/rooms_2_diff.png "the far room (against the near room from the same place)")
candela_same_or_fail(${dir}/rooms_3.png ${dir}/rooms_4.png ${dir}/rooms_3_diff.png "the far room after a move in it (against the near room)")
execute_process(COMMAND ${CANDELA} compare ${dir}/rooms_1.png ${dir}/rooms_3.png --check RESULT_VARIABLE code OUTPUT_QUIET ERROR_QUIET)
if(code EQUAL 0)
  message(FATAL_ERROR "the move in the far room did not change the view: the test compares nothing")
endif()
