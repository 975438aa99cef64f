# `candela compare --batches` on real renders: three sets of 4 `--spp-shard K/4`
# batches of a scene at 64x64, 8 spp each: a and b differ only in --seed, d is biased dark
# (--max-depth 2 instead of the default). a vs b (and b vs a's saved mean with its standard
# error) must pass; a vs d must show a clearly positive z of the mean.
#   cmake -DCANDELA=... -DSCENE=... -DOUT=... -DOTHER_SIZE_IMAGE=... -P compare_batches.cmake
set(ENV{CANDELA_DEBUG_GL} 1)
file(MAKE_DIRECTORY ${OUT})
foreach(set "a;1;8" "b;2;8" "d;3;2")
  list(GET set 0 name)
  list(GET set 1 seed)
  list(GET set 2 depth)
  set(${name}_files)
  foreach(k 0 1 2 3)
    execute_process(COMMAND ${CANDELA} render ${SCENE} -o ${OUT}/batches_${name}_${k}.exr --raytrace path --spp 32
                            --spp-shard ${k}/4 --seed ${seed} --max-depth ${depth} --size 64x64 --quiet
                    RESULT_VARIABLE code ERROR_VARIABLE err)
    if(NOT code EQUAL 0)
      message(FATAL_ERROR "render ${name} ${k} failed: ${err}")
    endif()
    list(APPEND ${name}_files ${OUT}/batches_${name}_${k}.exr)
  endforeach()
endforeach()

# Runs compare with ARGN, expects exit 0 and no non-finite pixel, and sets <prefix>_passing and
# <prefix>_z (the z of the mean).
function(run_compare prefix)
  execute_process(COMMAND ${CANDELA} compare ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("compare ${prefix}:\n${out}${err}")
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "compare ${prefix}: exit ${code}")
  endif()
  if(NOT out MATCHES "nonfinite 0\n")
    message(FATAL_ERROR "compare ${prefix}: non-finite pixels in the batches")
  endif()
  if(NOT out MATCHES "pixels_passing ([0-9.]+) % \\(\\|z\\| < 5\\)")
    message(FATAL_ERROR "compare ${prefix}: no pixels_passing line")
  endif()
  set(${prefix}_passing ${CMAKE_MATCH_1} PARENT_SCOPE)
  if(NOT out MATCHES "z_of_mean (-?[0-9.]+)\n")
    message(FATAL_ERROR "compare ${prefix}: no finite z_of_mean")
  endif()
  set(${prefix}_z ${CMAKE_MATCH_1} PARENT_SCOPE)
endfunction()

# Same scene, other seed. With 4 batches a side z has heavy tails (Student t, ~6 degrees of
# freedom), hence 99 % rather than the 99.9 % of many batches.
run_compare(same --batches ${a_files} --against ${b_files} --z-map ${OUT}/batches_z.png
            --save-mean ${OUT}/batches_a_mean.exr --save-stderr ${OUT}/batches_a_se.exr)
string(REPLACE "-" "" same_abs_z "${same_z}")
if(same_passing LESS 99 OR same_abs_z GREATER 4)
  message(FATAL_ERROR "equal renders flagged: ${same_passing} % passing, z of mean ${same_z}")
endif()
foreach(image batches_a_mean.exr batches_a_se.exr)
  execute_process(COMMAND ${CANDELA} compare ${OUT}/${image} ${OUT}/${image} --check RESULT_VARIABLE code)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "${image} has non-finite values")
  endif()
endforeach()
if(NOT EXISTS ${OUT}/batches_z.png)
  message(FATAL_ERROR "--z-map wrote nothing")
endif()

# Against a's mean with its standard error (the reference form).
run_compare(ref --batches ${b_files} --against ${OUT}/batches_a_mean.exr --ref-stderr ${OUT}/batches_a_se.exr)
string(REPLACE "-" "" ref_abs_z "${ref_z}")
if(ref_passing LESS 99 OR ref_abs_z GREATER 4)
  message(FATAL_ERROR "equal render vs reference flagged: ${ref_passing} % passing, z of mean ${ref_z}")
endif()

# Truncated paths are darker: a (depth 8) is brighter than d (depth 2).
run_compare(biased --batches ${a_files} --against ${d_files})
if(NOT biased_z GREATER 6)
  message(FATAL_ERROR "--max-depth 2 not detected: z of mean ${biased_z}")
endif()

# Bad input: one batch, and an image of another size (exit 2, naming the file).
list(GET a_files 0 a0)
execute_process(COMMAND ${CANDELA} compare --batches ${a0} --against ${b_files} RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 2 OR NOT err MATCHES "at least 2 batch images")
  message(FATAL_ERROR "one batch: exit ${code}: ${err}")
endif()
execute_process(COMMAND ${CANDELA} compare --batches ${a_files} --against ${OTHER_SIZE_IMAGE} ${b_files}
                RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 2 OR NOT err MATCHES "CesiumLogoFlat.png is 211x211 but .*batches_a_0.exr is 64x64")
  message(FATAL_ERROR "mismatched size: exit ${code}: ${err}")
endif()
message("same seed-to-seed: ${same_passing} % passing, z ${same_z}; vs reference: ${ref_passing} %, z ${ref_z}; "
        "--max-depth 2: z ${biased_z}")
