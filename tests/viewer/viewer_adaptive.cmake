# Adaptive quality in the viewer (samples/viewer/adaptive_quality.hpp) under xvfb-run, on the
# Cornell box:
# 1. tests/viewer/adaptive.script turns the camera with a 20 ms target: the log must show the
#    moving frames going to a scaled level, the screenshot taken while moving must be smaller
#    than the scene, and after the camera stops the viewer must render one full-quality frame
#    and keep showing it (not render it again): the last screenshot says "quality full" and
#    equals `candela render` at the golden tolerance.
# 2. adaptive_off.script makes the same movement with it off: every frame full quality.
# 3. adaptive_reduced.script: the reduced level at full size equals `candela render --set` with
#    the reductions the log names (the viewer renders what it says) and differs from the full
#    render (the reductions change the image: none is a knob that does nothing here).
# Each run's log must report 0 non-finite radiance values for every screenshot; each compared
# PNG goes through `candela compare --check` (which also fails on NaN/Inf).
#   cmake -DCANDELA=... -DSCENE=... -DDIR=... -DOUT=... -P viewer_adaptive.cmake
include(${CMAKE_CURRENT_LIST_DIR}/../cmake/steps.cmake)
set(size 320x240)
set(dir ${OUT}/viewer_adaptive)
file(REMOVE_RECURSE ${dir})
file(MAKE_DIRECTORY ${dir})

# Runs the viewer with SCRIPT for FRAMES frames; the log (stderr) goes to out_var. gi.budget=0:
# the Cornell box's GI probes converge before a frame (as in `candela render`), not over frames,
# so a still view needs no more frames for them and the frames rendered count the still view's.
function(run_view script frames out_var)
  candela_view_or_fail(${dir} err ${SCENE} --size ${size} --script ${DIR}/${script} --frames ${frames}
                       --screenshot ${dir}/${script}.png --no-vsync --set gi.budget=0)
  string(REGEX MATCHALL "viewer: wrote [^\n]*" wrote "${err}")
  foreach(line IN LISTS wrote)
    if(NOT line MATCHES ", 0 non-finite radiance values")
      message(FATAL_ERROR "a screenshot has NaN or infinite radiance: ${line}")
    endif()
  endforeach()
  set(${out_var} "${err}" PARENT_SCOPE)
endfunction()

# 1. Moving, then still. 600 frames: the still frames after the movement are not rendered again,
# so they are quick (a few ms), and together they outlast the quarter of a second the viewer waits.
run_view(adaptive.script 600 log)
if(NOT log MATCHES "frame [0-9]+: quality scaled, scale 0\\.[0-9]+")
  message(FATAL_ERROR "the moving frames never went to a scaled level (target 20 ms)")
endif()
if(NOT log MATCHES "wrote adaptive_moving\\.png at quality (reduced|scaled) \\(([0-9]+)x([0-9]+)\\)")
  message(FATAL_ERROR "the screenshot taken while moving was not at a reduced level")
endif()
if(NOT CMAKE_MATCH_2 LESS 320 OR NOT CMAKE_MATCH_3 LESS 240)
  message(FATAL_ERROR "the moving screenshot is ${CMAKE_MATCH_2}x${CMAKE_MATCH_3}: not scaled down from ${size}")
endif()
if(NOT log MATCHES "wrote [^\n]*adaptive\\.script\\.png at quality full \\(320x240\\)")
  message(FATAL_ERROR "the last frame (still for 575 frames) was not at full quality: did 575 frames take < 0.25 s?")
endif()
# Full quality: frame 0, frame 1 (frame 0 did the GI probes' work, which counts as converging)
# and the still view after the movement, once: not the hundreds of still frames after it.
if(NOT log MATCHES "frames rendered by quality level: full ([0-9]+),")
  message(FATAL_ERROR "the log does not count the frames rendered at full quality")
endif()
if(CMAKE_MATCH_1 GREATER 3)
  message(FATAL_ERROR "${CMAKE_MATCH_1} frames rendered at full quality: a still view should be rendered once, then shown")
endif()
if(NOT log MATCHES "([0-9]+) frames with the view moving: median frame ([0-9.]+) ms \\(([0-9.]+) fps\\); adaptive quality on")
  message(FATAL_ERROR "the log does not report the moving frames' frame rate")
endif()
set(on_fps ${CMAKE_MATCH_3})
candela_render_or_fail("candela render" ${SCENE} --size ${size} --camera 0 -o ${dir}/reference.png)
candela_same_or_fail(${dir}/adaptive.script.png ${dir}/reference.png ${dir}/still_diff.png
                     "the still frame after the movement (against candela render)")

# 2. The same movement with adaptive quality off.
run_view(adaptive_off.script 30 log)
if(NOT log MATCHES "frames rendered by quality level: full 30\n")
  message(FATAL_ERROR "with adaptive quality off every frame must be rendered at full quality")
endif()
if(NOT log MATCHES "frames with the view moving: median frame ([0-9.]+) ms \\(([0-9.]+) fps\\); adaptive quality off")
  message(FATAL_ERROR "the log does not report the moving frames' frame rate (adaptive off)")
endif()
message("moving frames: ${on_fps} fps with adaptive quality on (target 20 ms), ${CMAKE_MATCH_2} fps off")
candela_same_or_fail(${dir}/adaptive_off.script.png ${dir}/reference.png ${dir}/off_diff.png
                     "the last frame with adaptive quality off (against candela render)")

# 3. The reduced level at full size.
run_view(adaptive_reduced.script 3 log)
if(NOT log MATCHES "adaptive quality reduced, target [0-9]+ ms; reduced: ([^\n]+)")
  message(FATAL_ERROR "the log does not name the reductions")
endif()
separate_arguments(reductions UNIX_COMMAND "${CMAKE_MATCH_1}")
set(set_args)
foreach(r IN LISTS reductions)
  list(APPEND set_args --set ${r})
endforeach()
message("reductions: ${set_args}")
candela_render_or_fail("candela render (reduced)" ${SCENE} --size ${size} --camera 0 ${set_args} -o ${dir}/reference_reduced.png)
candela_same_or_fail(${dir}/adaptive_reduced.png ${dir}/reference_reduced.png ${dir}/reduced_diff.png
                     "the viewer's reduced frame (against candela render with the reductions)")
execute_process(COMMAND ${CANDELA} compare ${dir}/adaptive_reduced.png ${dir}/reference.png --check
                RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("compare reduced vs full:\n${out}${err}")
if(NOT code EQUAL 4)
  message(FATAL_ERROR "the reduced frame should differ from the full-quality one (compare exit ${code}, expected 4)")
endif()
