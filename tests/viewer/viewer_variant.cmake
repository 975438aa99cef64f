# The viewer switches material variants live: SheenChair under xvfb-run with
# tests/viewer/variant.script (default -> variant 1 -> default, no reload of the file). The
# screenshot of variant 1 must equal `candela render --variant 1`, the one after switching back
# must equal the first (the golden tolerance), and the log must say the switch happened and that
# every screenshot's radiance had no NaN or infinity.
#   cmake -DCANDELA=... -DSCENE=... -DSCRIPT=... -DOUT=... -P viewer_variant.cmake
include(${CMAKE_CURRENT_LIST_DIR}/../cmake/steps.cmake)
set(size 160x120)
set(dir ${OUT}/viewer_variant)
file(REMOVE_RECURSE ${dir})
file(MAKE_DIRECTORY ${dir})
# gi.budget=0: any GI probes converge before each frame, so an image depends on the variant only.
candela_view_or_fail(${dir} err ${SCENE} --size ${size} --script ${SCRIPT} --set gi.budget=0 --no-vsync)
candela_log_says_or_fail("${err}" "the log" "material variant \\[1\\] 'Peacock Velvet'" "material variant default")
candela_clean_shots_or_fail("${err}" "variant_[a-z0-9_]+\\.png" 3 "of the variants")
candela_render_or_fail("candela render --variant 1" ${SCENE} --size ${size} --variant 1 -o ${dir}/variant_render.png)
candela_same_or_fail(${dir}/variant_1.png ${dir}/variant_render.png ${dir}/variant_1_diff.png
                     "the viewer's variant 1 (against candela render --variant 1)")
candela_same_or_fail(${dir}/variant_default.png ${dir}/variant_start.png ${dir}/variant_default_diff.png
                     "the viewer's default look after switching back (against the first frame)")
# And the switch changed the image: variant 1 is not the default look.
execute_process(COMMAND ${CANDELA} compare ${dir}/variant_1.png ${dir}/variant_start.png --check
                RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT code EQUAL 4)
  message(FATAL_ERROR "the viewer's variant 1 looks like the default (compare exit ${code}):\n${out}${err}")
endif()
