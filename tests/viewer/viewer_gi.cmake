# The viewer updates the GI probes over frames: on cornell_point, whose indirect light
# plans the probes, the viewer's default gi.budget leaves frame 1 unconverged (its screenshot
# differs from `candela render`, a still that converges before its frame), the log says
# "converging" at frame 0 and "converged" later, and the last frame equals `candela render` at the
# golden tolerance (the updates run in the same 64-probe batches). `--set gi.budget=0` is
# respected: converged at frame 0. The log lines are the panel's GI line (at this size the window
# shot is too short to show it; a taller --size shows it under the gi row).
#   cmake -DCANDELA=... -DSCENE=... -DSCRIPT=... -DOUT=... -DCHECK_WINDOW=... -P viewer_gi.cmake
include(${CMAKE_CURRENT_LIST_DIR}/../cmake/steps.cmake)
set(size 160x120)
file(REMOVE ${OUT}/viewer_gi_early.png ${OUT}/viewer_gi.png)
# 18 updates of 8x8x8 probes x 64 rays at 16384 rays per frame: 36 frames (the log says how many).
candela_view_or_fail(${OUT} err ${SCENE} --size ${size} --script ${SCRIPT}
                     --frames 90 --screenshot ${OUT}/viewer_gi.png --window-shot ${OUT}/viewer_gi_window.png --no-vsync)
if(NOT err MATCHES "frame 0: GI probes [0-9]+x[0-9]+x[0-9]+, [0-9]+ rays, [0-9]+ bounce\\(s\\): 0/[0-9]+ updates done \\(converging, 16384 rays/frame")
  message(FATAL_ERROR "the viewer did not start the GI probes converging at its default budget (16384 rays/frame)")
endif()
if(NOT err MATCHES "frame ([0-9]+): GI probes [^\n]*: converged \\([0-9]+ updates\\)")
  message(FATAL_ERROR "the GI probes did not converge within the run")
endif()
if(CMAKE_MATCH_1 LESS 10)
  message(FATAL_ERROR "the GI probes converged at frame ${CMAKE_MATCH_1}: the budget did not spread the updates")
endif()
candela_render_or_fail("candela render" ${SCENE} --size ${size} -o ${OUT}/viewer_gi_reference.png)
candela_same_or_fail(${OUT}/viewer_gi.png ${OUT}/viewer_gi_reference.png ${OUT}/viewer_gi_diff.png
                     "the viewer's converged frame (against candela render)")
execute_process(COMMAND ${CANDELA} compare ${OUT}/viewer_gi_early.png ${OUT}/viewer_gi_reference.png --check
                RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("compare frame 1 vs render:\n${out}${err}")
if(NOT code EQUAL 4)
  message(FATAL_ERROR "frame 1 should still be converging and differ from the still (compare exit ${code}, expected 4)")
endif()
execute_process(COMMAND ${PYTHON3} ${CHECK_WINDOW} ${OUT}/viewer_gi_window.png ${OUT}/viewer_gi.png
                RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "the window shot is not the scene beside the panel:\n${out}${err}")
endif()
# The user's --set gi.budget wins over the viewer's default: 0 converges before frame 0's image.
candela_view_or_fail(${OUT} err ${SCENE} --size ${size} --frames 2 --set gi.budget=0 --no-vsync)
if(NOT err MATCHES "frame 0: GI probes [^\n]*: converged \\([0-9]+ updates, before the frame: gi.budget=0\\)")
  message(FATAL_ERROR "--set gi.budget=0 was not respected by the viewer")
endif()
