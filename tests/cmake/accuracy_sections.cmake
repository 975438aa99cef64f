# Accuracy sweeps on a cluster: `bench accuracy` run one section per process (as cluster array tasks) and assembled
# gives the results.csv of the run in one process, and the same plots and strips. Also: assembly
# with a section missing fails (exit 1) naming its directory and label and writes nothing; a
# section run again on a complete directory skips it.
#   cmake -DCANDELA=... -DOUT=... -P accuracy_sections.cmake
#
# Compared: every column but the times (ms, iqr, frame_ms; a ray_tracer row's ms is its trace
# time) and pareto, which is computed from the times: two runs time differently, so a row near
# the front can be on it in one and off it in the other. The errors (rmse, relmse, max, pct_over,
# ref_noise, rmse_no_occlusion) and at_noise_floor are the same to the printed digit: the images
# of two runs are identical on llvmpipe (checked over two whole quick sweeps in one process each).
# That the saved sections read back bit for bit (times and pareto included) is checked by every
# section run itself.
#
# The sections: ssao (raster rows against a traced reference), forward_deferred (times only: the
# report's other kind of section) and ray_tracer_depth (traced rows, whose ms is the trace time),
# each one to two seconds in a quick sweep on llvmpipe.
cmake_policy(VERSION 3.25)
set(SWEEP bench accuracy --quick --quiet --effect ssao --effect forward_deferred --effect ray_tracer_depth)
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})

function(run expect_code)
  execute_process(COMMAND ${CANDELA} ${SWEEP} ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL expect_code)
    message(FATAL_ERROR "candela ${SWEEP} ${ARGN}: exit ${code}, expected ${expect_code}\n${out}${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
  set(err "${err}" PARENT_SCOPE)
endfunction()

run(0 -o ${OUT}/one)
run(0 --list-sections)
string(REGEX REPLACE "\n$" "" labels "${out}")
string(REPLACE "\n" ";" labels "${labels}")
if(NOT labels STREQUAL "ssao on shadow_test.gltf;forward_deferred on generated:lights:N;ray_tracer_depth on cornell_box.gltf")
  message(FATAL_ERROR "--list-sections: unexpected sections: ${labels}")
endif()
list(LENGTH labels n)
math(EXPR last "${n} - 1")
set(dirs "")
foreach(k RANGE ${last})
  list(APPEND dirs --assemble ${OUT}/sections/${k})
endforeach()

# Every section but the first, then an assembly: section 0 is reported missing, nothing written.
foreach(k RANGE 1 ${last})
  run(0 --section ${k} --section-dir ${OUT}/sections/${k})
  message("${out}")
endforeach()
run(1 ${dirs} -o ${OUT}/assembled)
if(NOT err MATCHES "sections/0: section 0 \\(ssao on shadow_test.gltf\\) is missing or incomplete: no section.json")
  message(FATAL_ERROR "assembly without section 0 does not name it:\n${err}")
endif()
if(EXISTS ${OUT}/assembled/results.csv)
  message(FATAL_ERROR "assembly without section 0 wrote results.csv")
endif()
# Out-of-range index: exit 2.
run(2 --section ${n} --section-dir ${OUT}/sections/x)

run(0 --section 0 --section-dir ${OUT}/sections/0)
message("${out}")
run(0 --section 0 --section-dir ${OUT}/sections/0)
if(NOT out MATCHES "section 0 \\(ssao on shadow_test.gltf\\): [^\n]*sections/0 is complete, skipped")
  message(FATAL_ERROR "a complete section ran again:\n${out}")
endif()
run(0 ${dirs} -o ${OUT}/assembled)
message("${out}")

# results.csv column by column but the times and pareto (compare_accuracy_csv.cmake, which
# `candela farm`'s test uses too).
set(A ${OUT}/one/results.csv)
set(B ${OUT}/assembled/results.csv)
include(${CMAKE_CURRENT_LIST_DIR}/compare_accuracy_csv.cmake)

# The same plots and strips (their names; their pixels follow the rows' images and pareto).
file(GLOB one RELATIVE ${OUT}/one ${OUT}/one/*.svg ${OUT}/one/*.png)
file(GLOB assembled RELATIVE ${OUT}/assembled ${OUT}/assembled/*.svg ${OUT}/assembled/*.png)
if(NOT one STREQUAL assembled OR NOT EXISTS ${OUT}/assembled/report.md)
  message(FATAL_ERROR "plots and strips differ: '${one}' in one process, '${assembled}' assembled")
endif()
message("${n} sections; plots and strips ${one}")
