# References on a cluster: `candela farm reference` without a scheduler (the plain mode that GNU parallel,
# Kubernetes indexed jobs and HTCondor use): the scripts it writes, tasks run by index in any
# order, the merge equal to one process, idempotent reruns, and the refusals.
#   cmake -DCANDELA=... -DSCENE=cornell_box.gltf -DOUT=... -P farm_plain.cmake
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
set(ARGS --raytrace path --spp 6 --size 24x16 --seed 9 --quiet)

# Runs candela with ARGN; fails unless it exits with `expect` and its output matches `pattern`.
function(candela expect pattern)
  execute_process(COMMAND ${CANDELA} ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL expect OR NOT "${out}${err}" MATCHES "${pattern}")
    message(FATAL_ERROR "candela ${ARGN}: exit ${code} (expected ${expect}), output not matching '${pattern}':\n${out}${err}")
  endif()
  set(out "${out}${err}" PARENT_SCOPE)
endfunction()

# --dry-run prints the two Slurm scripts and writes nothing.
candela(0 "#SBATCH --array=0-2\n.*#SBATCH --partition=cpu\n.*farm task .*SLURM_ARRAY_TASK_ID.*farm finish.*--dependency=afterany"
        farm reference ${SCENE} -o ${OUT}/dry --shards 3 ${ARGS} --sbatch --partition=cpu --dry-run)
if(EXISTS ${OUT}/dry)
  message(FATAL_ERROR "--dry-run wrote ${OUT}/dry")
endif()

# Bad requests fail before anything is written (exit 2).
candela(2 "--shards 7 is more than --spp 6" farm reference ${SCENE} -o ${OUT}/bad --shards 7 ${ARGS})
candela(2 "needs --shards N" farm reference ${SCENE} -o ${OUT}/bad ${ARGS})
candela(2 "nope.gltf: no such file" farm reference ${OUT}/nope.gltf -o ${OUT}/bad --shards 2 ${ARGS})
candela(2 "not a farm directory" farm finish ${OUT})

# Three shards, run in reverse order through run-task.sh as a foreign scheduler would.
candela(0 "3 shard tasks" farm reference ${SCENE} -o ${OUT}/ref --shards 3 ${ARGS})
foreach(f farm.json tasks.txt run-task.sh slurm/array.sbatch slurm/finish.sbatch submit-slurm.sh)
  if(NOT EXISTS ${OUT}/ref/${f})
    message(FATAL_ERROR "farm reference did not write ${f}")
  endif()
endforeach()
file(STRINGS ${OUT}/ref/tasks.txt tasks)
list(LENGTH tasks n)
if(NOT n EQUAL 3)
  message(FATAL_ERROR "tasks.txt has ${n} lines, not one per shard (3)")
endif()
candela(1 "3 of 3 tasks .* are not complete:.*task 0: .*shard_0000.exr: no output yet" farm finish ${OUT}/ref)
foreach(i 2 1 0)
  execute_process(COMMAND ${OUT}/ref/run-task.sh ${i} RESULT_VARIABLE code)
  if(NOT code EQUAL 0)
    file(READ ${OUT}/ref/logs/task_${i}.log log)
    message(FATAL_ERROR "run-task.sh ${i}: exit ${code}\n${log}")
  endif()
endforeach()
file(READ ${OUT}/ref/logs/task_1.log log)
if(NOT log MATCHES "wrote .*shard_0001.exr \\(2 samples per pixel\\)")
  message(FATAL_ERROR "task 1's log does not show its shard:\n${log}")
endif()
candela(0 "all 3 tasks .* are complete" farm status ${OUT}/ref)
candela(0 "merged 3 shards" farm finish ${OUT}/ref)
candela(0 "" render ${SCENE} ${ARGS} -o ${OUT}/single.exr)
candela(0 "nonfinite 0" compare ${OUT}/ref/reference.exr ${OUT}/single.exr --tolerance 1e-5 --max-failing 0 --check)

# A rerun skips complete shards; a damaged one is rendered again.
candela(0 "shard_0002.exr is complete \\(2 samples per pixel\\): skipped" farm task ${OUT}/ref 2)
file(WRITE ${OUT}/ref/shards/shard_0001.exr "not an image")
candela(1 "task 1: .*shard_0001.exr: unreadable" farm status ${OUT}/ref)
candela(0 "shard_0001.exr is not complete \\(unreadable.*wrote" farm task ${OUT}/ref 1)
# The same farm command again reuses the directory; another job does not overwrite it.
candela(0 "holds this job already" farm reference ${SCENE} -o ${OUT}/ref --shards 3 ${ARGS})
candela(2 "farm.json describes another farm job" farm reference ${SCENE} -o ${OUT}/ref --shards 2 ${ARGS})

# merge refuses shards of another render, or the same shard twice, naming the files.
candela(0 "" render ${SCENE} --raytrace path --spp 6 --size 24x16 --seed 10 --spp-shard 1/3 --quiet -o ${OUT}/seed10.exr)
candela(2 "seed10.exr is a shard of another render than .*shard_0000.exr: candela:seed is '10'"
        merge ${OUT}/m.exr ${OUT}/ref/shards/shard_0000.exr ${OUT}/seed10.exr)
candela(2 "shard 0/3 is also in" merge ${OUT}/m.exr ${OUT}/ref/shards/shard_0000.exr ${OUT}/ref/shards/shard_0000.exr)
candela(0 "" render ${SCENE} --raytrace path --spp 6 --size 24x16 --seed 9 --set ao.radius=0.5 --spp-shard 1/3 --quiet -o ${OUT}/knob.exr)
candela(2 "candela:args" merge ${OUT}/m.exr ${OUT}/ref/shards/shard_0000.exr ${OUT}/knob.exr)
message("farm plain mode: all checks passed")
