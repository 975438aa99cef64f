# Runs the viewer under xvfb-run with a script for 60 frames, then compares its screenshot with
# `candela render` of the same camera and settings (the golden tolerance: compare --check), and
# checks that the docked panel is beside the scene, not over it: the window shot's scene region
# equals the screenshot pixel for pixel (tests/viewer/check_window_shot.py).
#   cmake -DCANDELA=... -DSCENE=... -DSCRIPT=... -DOUT=... -P viewer_smoke.cmake
include(${CMAKE_CURRENT_LIST_DIR}/steps.cmake)
find_program(XVFB_RUN xvfb-run)
if(NOT XVFB_RUN)
  message(FATAL_ERROR "xvfb-run is needed for the viewer test (apt-get install xvfb xauth)")
endif()
set(size 320x240)
execute_process(COMMAND ${XVFB_RUN} -a -s "-screen 0 1024x768x24" ${CANDELA} view ${SCENE} --size ${size} --script ${SCRIPT}
                        --frames 60 --screenshot ${OUT}/viewer.png --window-shot ${OUT}/viewer_window.png --no-vsync
                RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
message("view: exit ${code}\n${out}${err}")
if(NOT code EQUAL 0)
  message(FATAL_ERROR "the viewer failed")
endif()
candela_render_or_fail("candela render" ${SCENE} --size ${size} --effects all --set ssao.samples=8 --path forward
                       --camera 0 -o ${OUT}/viewer_reference.png)
candela_same_or_fail(${OUT}/viewer.png ${OUT}/viewer_reference.png ${OUT}/viewer_diff.png
                     "the viewer's screenshot (against candela render)")
# The window shot holds the panel too, beside the scene: the window is as tall as --size and
# wider, its left part is the screenshot exactly, its right part is the panel.
find_program(PYTHON3 python3 PATHS /usr/bin NO_DEFAULT_PATH)
find_program(PYTHON3 python3)
execute_process(COMMAND ${PYTHON3} ${CMAKE_CURRENT_LIST_DIR}/../viewer/check_window_shot.py ${OUT}/viewer_window.png ${OUT}/viewer.png
                RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("window shot vs screenshot:\n${out}${err}")
if(NOT code EQUAL 0)
  message(FATAL_ERROR "the viewer's panel covers the scene or is missing (see ${OUT}/viewer_window.png)")
endif()
