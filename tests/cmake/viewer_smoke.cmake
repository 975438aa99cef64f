# Runs the viewer under xvfb-run with a script for 60 frames, then compares its screenshot with
# `candela render` of the same camera and settings (the golden tolerance: compare --check).
#   cmake -DCANDELA=... -DSCENE=... -DSCRIPT=... -DOUT=... -P viewer_smoke.cmake
find_program(XVFB_RUN xvfb-run)
if(NOT XVFB_RUN)
  message(FATAL_ERROR "xvfb-run is needed for the viewer test (apt-get install xvfb xauth)")
endif()
set(size 320x240)
execute_process(COMMAND ${XVFB_RUN} -a -s "-screen 0 640x480x24" ${CANDELA} view ${SCENE} --size ${size} --script ${SCRIPT}
                        --frames 60 --screenshot ${OUT}/viewer.png --window-shot ${OUT}/viewer_window.png --no-vsync
                RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
message("view: exit ${code}\n${out}${err}")
if(NOT code EQUAL 0)
  message(FATAL_ERROR "the viewer failed")
endif()
execute_process(COMMAND ${CANDELA} render ${SCENE} --size ${size} --effects all --set ssao.samples=8 --path forward
                        --camera 0 -o ${OUT}/viewer_reference.png
                RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "candela render failed:\n${out}${err}")
endif()
execute_process(COMMAND ${CANDELA} compare ${OUT}/viewer.png ${OUT}/viewer_reference.png --check --heatmap ${OUT}/viewer_diff.png
                RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("compare viewer vs render:\n${out}${err}")
if(NOT code EQUAL 0)
  message(FATAL_ERROR "the viewer's screenshot differs from candela render (see ${OUT}/viewer_diff.png)")
endif()
# The window shot holds the panel too: it must differ from the bare image.
execute_process(COMMAND ${CANDELA} compare ${OUT}/viewer_window.png ${OUT}/viewer.png --check RESULT_VARIABLE code OUTPUT_QUIET ERROR_QUIET)
if(code EQUAL 0)
  message(FATAL_ERROR "the window shot shows no UI panel")
endif()
