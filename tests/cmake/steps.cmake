# Steps the cmake test scripts share (include() it; CANDELA must be set):
#   candela_render_or_fail(WHAT ARG...)    `candela render ARG...`; fails the test naming WHAT
#   candela_same_or_fail(A B HEATMAP WHAT) `candela compare A B --check` (the default tolerance,
#                                          no NaN/Inf) writing HEATMAP; fails saying WHAT differs
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
