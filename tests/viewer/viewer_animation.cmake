# The viewer plays glTF animation: Fox under xvfb-run with tests/viewer/animation.script
# (walk at 0.25 s and 0.5 s, scrub back, play at 4x, pause), then `view --animation Walk --time
# 0.5` from the command line, which must equal `candela render --animation Walk --time 0.5` (the
# golden tolerance); check_animation.py compares the screenshots (the fox's region changes
# between the poses, scrubbing back gives the same image, paused frames are identical, none is
# black). The log must say every screenshot's radiance had no NaN
# or infinity, and that a paused viewer posed nothing more.
#   cmake -DCANDELA=... -DSCENE=... -DSCRIPT=... -DOUT=... -DPYTHON3=... -DCHECK=... -P viewer_animation.cmake
include(${CMAKE_CURRENT_LIST_DIR}/../cmake/steps.cmake)
set(size 200x150)
set(dir ${OUT}/viewer_animation)
file(REMOVE_RECURSE ${dir})
file(MAKE_DIRECTORY ${dir})
# gi.budget=0: any GI probes converge before each frame, so an image depends on the pose only.
candela_view_or_fail(${dir} err ${SCENE} --size ${size} --script ${SCRIPT} --set gi.budget=0 --no-vsync)
candela_log_says_or_fail("${err}" "the log"
    "start: animation 'Survey' \\(0 of 3\\), 0.000 s of [0-9.]+ s, playing"
    "frame 0: animation: animation 'Walk' \\(1 of 3\\), 0.000 s"
    "frame 1: time: animation 'Walk' \\(1 of 3\\), 0.250 s of [0-9.]+ s, paused"
    "frame 15: pause: animation 'Walk' \\(1 of 3\\), [0-9.]+ s of [0-9.]+ s, paused, speed 4.00x"
    "reference restarts: new pose at 0.300 s"
    "reference: motion blur, the tracer poses the scene over the shutter 0.29[0-9]+..0.30[0-9]+ s")
candela_clean_shots_or_fail("${err}" "anim_[a-z0-9_]+\\.png \\(animation 1 at [0-9.]+ s\\)" 7 "of animation 1")
# Posed at frames 0 (Walk), 1, 4, 7 (scrubs), once per played frame (11..15, fewer when slow
# frames reach the end first), 25 (scrub) and 27 (the shutter's motion): 7 to 11; never while
# paused (frames 16..24, 26, 28..31).
if(NOT err MATCHES "posed the scene ([0-9]+) times in 32 frames")
  message(FATAL_ERROR "the viewer did not report its poses")
endif()
if(CMAKE_MATCH_1 GREATER 12)
  message(FATAL_ERROR "the viewer posed the scene ${CMAKE_MATCH_1} times: more than once per change (paused frames posed again)")
endif()
if(CMAKE_MATCH_1 LESS 7)
  message(FATAL_ERROR "the viewer posed the scene only ${CMAKE_MATCH_1} times: scrubs or played frames were not posed")
endif()
# The command line: posed like `render --animation Walk --time 0.5` (the set-up poses the scene
# before framing and lighting it, so the camera is that of render, not of the script's run).
candela_view_or_fail(${dir} err ${SCENE} --size ${size} --animation Walk --time 0.5
                     --frames 3 --screenshot ${dir}/anim_cli.png --set gi.budget=0 --no-vsync)
if(NOT err MATCHES "start: animation 'Walk' \\(1 of 3\\), 0.500 s of [0-9.]+ s, paused")
  message(FATAL_ERROR "view --animation Walk --time 0.5 did not start paused at 0.5 s of the walk")
endif()
candela_render_or_fail("candela render --animation Walk --time 0.5"
                       ${SCENE} --size ${size} --animation Walk --time 0.5 -o ${dir}/anim_render.png)
candela_same_or_fail(${dir}/anim_cli.png ${dir}/anim_render.png ${dir}/anim_cli_diff.png
                     "the viewer's --animation Walk --time 0.5 (against candela render's)")
execute_process(COMMAND ${PYTHON3} ${CHECK} ${dir} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("check_animation.py:\n${out}${err}")
if(NOT code EQUAL 0)
  message(FATAL_ERROR "the viewer's animation screenshots are wrong (see ${dir})")
endif()
