# After golden.altered (a golden test that must fail): it failed because the render differs from
# the golden, not for another reason (no GL, a crash, a missing file). The check script removes
# the candidate and diff at its start and, on success, at its end; so both present means this run
# rendered, compared and found a difference.
#   cmake -DCANDELA=candela -DDIR=<build>/candela-golden -DNAME=TEST -DGOLDEN=G.png -P check_reported.cmake
foreach(kind candidate diff)
  if(NOT EXISTS "${DIR}/${NAME}.${kind}.png")
    message(FATAL_ERROR "${NAME} left no ${kind} image (${DIR}/${NAME}.${kind}.png): it did not fail on the comparison")
  endif()
endforeach()
# And the candidate really is beyond the tolerance: compare --check exits 4.
execute_process(COMMAND "${CANDELA}" compare "${DIR}/${NAME}.candidate.png" "${GOLDEN}" --check
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 4)
  message(FATAL_ERROR "candela compare --check of ${NAME}'s candidate exited ${rc}, expected 4 (beyond tolerance):\n${out}${err}")
endif()
message("${NAME} failed on the comparison, as it should:\n${out}")
