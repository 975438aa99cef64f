# Steps the cmake test scripts share (include() it; CANDELA must be set):
#   candela_render_or_fail(WHAT ARG...)    `candela render ARG...`; fails the test naming WHAT
#   candela_same_or_fail(A B HEATMAP WHAT) `candela compare A B --check` (the default tolerance,
#                                          no NaN/Inf) writing HEATMAP; fails saying WHAT differs
#   candela_view_or_fail(DIR LOG_VAR ARG...) `candela view ARG...` under xvfb-run in DIR; LOG_VAR: its log
#   candela_log_says_or_fail(LOG WHAT REGEX...) every REGEX matches LOG, else fails naming WHAT and the REGEX
#   candela_clean_shots_or_fail(LOG SHOT COUNT WHAT) LOG says COUNT times that it wrote a screenshot
#                                          matching SHOT with 0 non-finite radiance values
function(candela_render_or_fail what)
  execute_process(COMMAND ${CANDELA} render ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 300)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "${what} failed (exit ${code}):\n${out}${err}")
  endif()
endfunction()

function(candela_same_or_fail a b heatmap what)
  execute_process(COMMAND ${CANDELA} compare ${a} ${b} --check --heatmap ${heatmap}
                  RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("compare ${a} ${b}:\n${out}${err}")
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "${what} differs (see ${heatmap})")
  endif()
endfunction()

# The viewer tests' run: `candela view ARGS...` under xvfb-run in `dir`; fails on a non-zero exit
# (or without xvfb-run), prints the log, and sets `log_var` to the viewer's log (its stderr).
function(candela_view_or_fail dir log_var)
  find_program(XVFB_RUN xvfb-run)
  if(NOT XVFB_RUN)
    message(FATAL_ERROR "xvfb-run is needed for the viewer tests (apt-get install xvfb xauth)")
  endif()
  execute_process(COMMAND ${XVFB_RUN} -a -s "-screen 0 1024x768x24" ${CANDELA} view ${ARGN}
                  WORKING_DIRECTORY ${dir}
                  RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 600)
  message("view ${ARGN}: exit ${code}\n${out}${err}")
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "the viewer failed (exit ${code})")
  endif()
  set(${log_var} "${err}" PARENT_SCOPE)
endfunction()

# Every regular expression matches `log`, else the test fails naming `what` (whose log) and the
# first one missing.
function(candela_log_says_or_fail log what)
  foreach(line IN LISTS ARGN)
    if(NOT log MATCHES "${line}")
      message(FATAL_ERROR "${what} does not say: ${line}")
    endif()
  endforeach()
endfunction()

# The viewer's log says exactly `count` times that it wrote a screenshot whose name and note match
# `shot` (a regular expression) with 0 non-finite radiance values, else the test fails naming `what`.
function(candela_clean_shots_or_fail log shot count what)
  string(REGEX MATCHALL "wrote ${shot}[^\n]*, 0 non-finite radiance values" clean "${log}")
  list(LENGTH clean n_clean)
  if(NOT n_clean EQUAL ${count})
    message(FATAL_ERROR "expected ${count} screenshots ${what} with 0 non-finite radiance values, the log has ${n_clean}")
  endif()
endfunction()
