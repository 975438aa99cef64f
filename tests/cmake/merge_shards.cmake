# Renders 4 spp in one run and as two shards, merges the shards, and compares with the one run.
foreach(args "full;--spp-shard;0/1" "s0;--spp-shard;0/2" "s1;--spp-shard;1/2")
  list(POP_FRONT args name)
  execute_process(COMMAND ${CANDELA} render ${SCENE} -o ${OUT}/merge_${name}.exr --raytrace path --spp 4 --size 16x16 ${args}
                  RESULT_VARIABLE code ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "render ${name} failed: ${err}")
  endif()
endforeach()
execute_process(COMMAND ${CANDELA} merge ${OUT}/merge_merged.exr ${OUT}/merge_s0.exr ${OUT}/merge_s1.exr RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "merge failed: ${err}")
endif()
# compare --check also fails on non-finite values in either image.
execute_process(COMMAND ${CANDELA} compare ${OUT}/merge_merged.exr ${OUT}/merge_full.exr --tolerance 1e-5 --max-failing 0 --check
                RESULT_VARIABLE code OUTPUT_VARIABLE out)
message("${out}")
if(NOT code EQUAL 0)
  message(FATAL_ERROR "merged shards differ from the single run")
endif()
