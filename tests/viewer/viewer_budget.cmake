# The error budget in the viewer (samples/viewer/budget_mode.hpp) under xvfb-run, on
# cornell_point at 160x120 (the statistics do not depend on the size, only on the aspect):
# 1. tests/viewer/budget.script: `budget 0.1` chooses the raster candidate `candela info
#    --error-budget 0.1` chooses (the log prints the same chosen and runner-up lines) from the
#    same statistics, and the frame equals `candela render --error-budget 0.1`; `budget 0.008`
#    has no raster candidate within it: the reference mode traces the view (path, shown as the
#    reference) and refines it; `budget 0.1` again gives the reference back; `off` gives back the
#    settings from before (the frame equals the first one) and the reference.
# 2. `candela view --error-budget 0.008`: the budget is on from the first frame, traced, and the
#    raster frame under the reference equals `candela render` at the most accurate raster
#    candidate's settings.
# Every screenshot's radiance and every reference image read back must be free of NaN and
# infinity (the log counts them); each compared PNG goes through `candela compare --check`.
#   cmake -DCANDELA=... -DSCENE=... -DSCRIPT=... -DOUT=... -P viewer_budget.cmake
include(${CMAKE_CURRENT_LIST_DIR}/../cmake/steps.cmake)
set(size 160x120)
set(dir ${OUT}/viewer_budget)
file(REMOVE_RECURSE ${dir})
file(MAKE_DIRECTORY ${dir})

function(check_screenshots log expected)
  string(REGEX MATCHALL "viewer: wrote [^\n]*" wrote "${log}")
  list(LENGTH wrote n)
  if(NOT n EQUAL ${expected})
    message(FATAL_ERROR "expected ${expected} screenshots in the log, found ${n}")
  endif()
  foreach(line IN LISTS wrote)
    if(NOT line MATCHES ", 0 non-finite radiance values")
      message(FATAL_ERROR "a screenshot has NaN or infinite radiance: ${line}")
    endif()
    if(line MATCHES "\\(reference" AND NOT line MATCHES "\\(reference path at [1-9][0-9]* spp: 0 non-finite values\\)$")
      message(FATAL_ERROR "the reference has NaN or infinite values (or no sample): ${line}")
    endif()
  endforeach()
endfunction()

# The GI probes are the user's --set over every choice (a user's knob wins over the budget's, in
# the viewer as in render): 4 probes along the longest axis and 64 rays. The most accurate raster
# candidate plans 16 probes (4096 in this room) and 256 rays, which took four times ~25 s of
# this test's ~60 s (CI time); what is tested here is the choice and the mode switches, and
# GI's own convergence in the viewer is viewer.gi_budget's.
set(gi --set gi.budget=0 --set gi.probes=4 --set gi.rays=64)

# What `candela info` chooses for the same view at each budget (the same statistics: the
# viewer's camera is the scene's first, at the same aspect).
foreach(e 0.1 0.008)
  execute_process(COMMAND ${CANDELA} info ${SCENE} --size ${size} --error-budget ${e}
                  RESULT_VARIABLE code OUTPUT_VARIABLE info_${e} ERROR_VARIABLE info_err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "candela info --error-budget ${e} failed (exit ${code}):\n${info_${e}}${info_err}")
  endif()
endforeach()
string(REGEX MATCH "chosen: ([a-z_]+) \\(" _ "${info_0.1}")
set(raster "${CMAKE_MATCH_1}")
if(raster STREQUAL "")
  message(FATAL_ERROR "candela info --error-budget 0.1 chose no raster candidate on ${SCENE}:\n${info_0.1}")
endif()
if(NOT info_0.008 MATCHES "chosen: the path tracer")
  message(FATAL_ERROR "candela info --error-budget 0.008 did not choose the tracer (the test needs a budget no raster candidate meets):\n${info_0.008}")
endif()
string(REGEX MATCH "runner-up: ([a-z_]+) \\(" _ "${info_0.1}")
set(raster_runner_up "${CMAKE_MATCH_1}")
string(REGEX MATCH "runner-up: ([a-z_]+) \\(" _ "${info_0.008}")
set(most_accurate "${CMAKE_MATCH_1}")
string(REGEX MATCH "statistics: (indirect [^\n]*)" _ "${info_0.1}")
set(info_stats "${CMAKE_MATCH_1}")

# 1. The script.
candela_view_or_fail(${dir} log ${SCENE} --size ${size} --script ${SCRIPT} ${gi} --no-vsync)
check_screenshots("${log}" 5)
candela_log_says_or_fail("${log}" "the log"
    "frame 3: error budget 0.1 \\(model built-in[^\n]*statistics of this view \\([0-9]+ ms\\): ${info_stats}"
    "frame 3: chosen: ${raster} \\([^\n]*<= 0.1\n"
    "frame 3: runner-up: ${raster_runner_up} \\([^\n]*rejected: predicted error above 0.1\n"
    "frame 6: chosen: the path tracer \\(reference mode path, shown as the reference\\): no raster candidate is predicted within the budget 0.008"
    "frame 6: runner-up: ${most_accurate} \\("
    "frame 6: error budget: reference path, show reference \\(the frame is traced"
    "wrote budget_trace.png[^\n]*\\(reference path at [1-9][0-9]* spp: 0 non-finite values\\)"
    "frame 31: chosen: ${raster} \\("
    "frame 31: error budget: reference off \\(show split\\) \\(as before the frame was traced\\)"
    "frame 34: chosen: the path tracer"
    "frame 36: error budget off: the settings from before it was on are back, reference off \\(show split\\)")
if(log MATCHES "wrote budget_(start|0.1|0.1_again|off).png[^\n]*\\(reference")
  message(FATAL_ERROR "the reference ran where no budget traced the frame")
endif()
candela_render_or_fail("candela render --error-budget 0.1" ${SCENE} --size ${size} --error-budget 0.1 ${gi}
                       -o ${dir}/render_0.1.png)
candela_same_or_fail(${dir}/budget_0.1.png ${dir}/render_0.1.png ${dir}/budget_0.1_diff.png
                     "the viewer's frame at budget 0.1 (against candela render --error-budget 0.1)")
candela_same_or_fail(${dir}/budget_0.1_again.png ${dir}/render_0.1.png ${dir}/budget_0.1_again_diff.png
                     "the viewer's frame at budget 0.1 after a traced choice (against candela render --error-budget 0.1)")
candela_same_or_fail(${dir}/budget_off.png ${dir}/budget_start.png ${dir}/budget_off_diff.png
                     "the viewer's frame after the budget is off (against the frame before it was on)")
# The choice changed the frame. On cornell_point `reduced` differs from the defaults in a few
# pixels only (there is no SSAO or RSM to lower), so bit for bit.
execute_process(COMMAND ${CANDELA} compare ${dir}/budget_0.1.png ${dir}/budget_start.png --tolerance 0 --max-failing 0 --check
                RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT code EQUAL 4)
  message(FATAL_ERROR "the frame at budget 0.1 (${raster}) is the default settings' frame (compare exit ${code}):\n${out}${err}")
endif()
# The traced choice changed the raster frame under the reference too (the most accurate raster
# candidate: 4x anti-aliasing, GI always).
execute_process(COMMAND ${CANDELA} compare ${dir}/budget_trace.png ${dir}/budget_start.png --check
                RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT code EQUAL 4)
  message(FATAL_ERROR "the raster frame at ${most_accurate} looks like the default settings' (compare exit ${code}):\n${out}${err}")
endif()

# 2. --error-budget on the command line: chosen before the first frame.
candela_view_or_fail(${dir} log2 ${SCENE} --size ${size} --error-budget 0.008 --frames 12 --screenshot ${dir}/budget_option.png
                     ${gi} --no-vsync)
check_screenshots("${log2}" 1)
candela_log_says_or_fail("${log2}" "the log of view --error-budget 0.008" "frame 0: error budget 0.008 \\(model built-in" "frame 0: chosen: the path tracer"
             "frame 0: error budget: reference path, show reference"
             "wrote [^\n]*budget_option.png[^\n]*\\(reference path at [1-9][0-9]* spp: 0 non-finite values\\)")
# The raster frame under the traced view renders at the most accurate raster candidate: the
# settings info's runner-up line names, given to `candela render`. (A live switch plans as a fresh
# renderer does too: unit test GiTest.ThresholdChangedLiveGivesTheImageOfAFreshRenderer.)
string(REGEX MATCH "runner-up: ${most_accurate} \\(([^)]*)\\)" _ "${info_0.008}")
separate_arguments(most_accurate_args UNIX_COMMAND "${CMAKE_MATCH_1}")
candela_render_or_fail("candela render at ${most_accurate}" ${SCENE} --size ${size} ${most_accurate_args} ${gi}
                       -o ${dir}/render_${most_accurate}.png)
candela_same_or_fail(${dir}/budget_option.png ${dir}/render_${most_accurate}.png ${dir}/budget_option_diff.png
                     "the raster frame under the view traced from the first frame (against candela render at ${most_accurate})")
