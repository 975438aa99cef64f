# `candela batch`: six jobs in one process, two of them bad (a missing scene, an
# unknown knob). The bad ones are reported with their index and the batch goes on (exit 2); every
# GL object a job made is freed after it; each good job's image is pixel-identical to `candela
# render` with the same arguments (a raster .png on the deferred path, a .exr with peeling, a
# traced .exr), also when it reuses the programs an earlier job compiled (job 6 = job 1). A text
# jobs file (one command line per job) renders the same image; a broken JSON file is exit 2.
#   cmake -DCANDELA=... -DSOURCE=... -DOUT=... -P batch.cmake
set(ENV{CANDELA_DEBUG_GL} 1)
file(MAKE_DIRECTORY ${OUT})
set(SCENES ${SOURCE}/samples/scenes)
# Small and cheap (CI time): GI off (gi.threshold=1; its probe tracing is most of a frame on
# llvmpipe), 128-texel shadow maps.
set(CHEAP --set gi.threshold=1 --set shadows.resolution=128)
set(job1 ${SCENES}/cornell_point.gltf --size 48x48 --path deferred ${CHEAP} -o ${OUT}/batch_1.png)
set(job3 ${SCENES}/transparency.gltf -o ${OUT}/batch_3.exr --size 40x32 --set transparency.mode=peeling --set shadows.resolution=128)
set(job5 ${SCENES}/cornell_box.gltf -o ${OUT}/batch_5.exr --size 16x16 --raytrace path --spp 1 --seed 7)
file(WRITE ${OUT}/batch_jobs.json "{\"jobs\": [
  {\"args\": [\"${SCENES}/cornell_point.gltf\", \"--size\", \"48x48\", \"--path\", \"deferred\", \"--set\", \"gi.threshold=1\", \"--set\", \"shadows.resolution=128\", \"-o\", \"${OUT}/batch_1.png\"]},
  {\"scene\": \"${SCENES}/nope.gltf\", \"output\": \"${OUT}/batch_2.png\"},
  {\"scene\": \"${SCENES}/transparency.gltf\", \"output\": \"${OUT}/batch_3.exr\", \"size\": [40, 32], \"set\": {\"transparency.mode\": \"peeling\", \"shadows.resolution\": 128}},
  {\"scene\": \"${SCENES}/cornell_point.gltf\", \"output\": \"${OUT}/batch_4.png\", \"set\": [\"ssao.bogus=1\"]},
  \"${SCENES}/cornell_box.gltf -o ${OUT}/batch_5.exr --size 16x16 --raytrace path --spp 1 --seed 7\",
  {\"scene\": \"${SCENES}/cornell_point.gltf\", \"size\": \"48x48\", \"path\": \"deferred\", \"set\": {\"gi.threshold\": 1, \"shadows.resolution\": 128}, \"output\": \"${OUT}/batch_6.png\"}
]}\n")
file(REMOVE ${OUT}/batch_1.png ${OUT}/batch_3.exr ${OUT}/batch_5.exr ${OUT}/batch_6.png)
execute_process(COMMAND ${CANDELA} batch ${OUT}/batch_jobs.json --timings RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("batch: exit ${code}\n${out}${err}")
if(NOT code EQUAL 2)
  message(FATAL_ERROR "batch with two bad jobs: expected exit 2, got ${code}")
endif()
foreach(regex "batch_jobs.json: job 2: error: [^\n]*nope.gltf: no such file"
              "batch_jobs.json: job 4: error: --set: unknown knob 'ssao.bogus'"
              "6 job\\(s\\), 4 ok, 2 failed: job 2 \\(exit 2\\), 4 \\(exit 2\\)"
              "GL objects all freed after every job")
  if(NOT "${err}" MATCHES "${regex}")
    message(FATAL_ERROR "batch output does not match: ${regex}")
  endif()
endforeach()

# Pixel-identical: no difference at all (tolerance 0, no failing pixel allowed).
function(expect_identical a b)
  execute_process(COMMAND ${CANDELA} compare ${a} ${b} --tolerance 0 --max-failing 0 --check RESULT_VARIABLE c OUTPUT_VARIABLE o ERROR_VARIABLE e)
  if(NOT c EQUAL 0)
    message(FATAL_ERROR "${a} differs from ${b} (exit ${c}):\n${o}${e}")
  endif()
  # Every image a test writes is checked for NaN/Inf (identical NaNs would still compare equal).
  if(NOT o MATCHES "nonfinite 0")
    message(FATAL_ERROR "${a} or ${b} has NaN/Inf pixels:\n${o}")
  endif()
  message("identical: ${a} ${b}")
endfunction()
foreach(n 1 3 5)
  string(REPLACE "batch_${n}" "render_${n}" render_args "${job${n}}")
  execute_process(COMMAND ${CANDELA} render ${render_args} --quiet RESULT_VARIABLE c ERROR_VARIABLE e)
  if(NOT c EQUAL 0)
    message(FATAL_ERROR "render ${render_args}: exit ${c}\n${e}")
  endif()
  file(GLOB image ${OUT}/batch_${n}.*)
  string(REPLACE "batch_${n}" "render_${n}" render_image "${image}")
  expect_identical(${image} ${render_image})
endforeach()
expect_identical(${OUT}/batch_6.png ${OUT}/batch_1.png)

# A text file: one command line per job ('#' comments, "render" may lead).
file(WRITE ${OUT}/batch_jobs.txt "# one job\nrender ${SCENES}/cornell_point.gltf --size 48x48 --path deferred --set gi.threshold=1 --set shadows.resolution=128 -o \"${OUT}/batch_text.png\"\n")
# candela batch FILE must exit with `code` and say `pattern` on stderr.
function(expect_batch file code pattern)
  execute_process(COMMAND ${CANDELA} batch ${file} RESULT_VARIABLE c ERROR_VARIABLE e)
  if(NOT c EQUAL ${code} OR NOT "${e}" MATCHES "${pattern}")
    message(FATAL_ERROR "batch ${file}: expected exit ${code} and '${pattern}', got ${c}\n${e}")
  endif()
endfunction()
expect_batch(${OUT}/batch_jobs.txt 0 "1 job\\(s\\), 1 ok, 0 failed")
expect_identical(${OUT}/batch_text.png ${OUT}/render_1.png)

file(WRITE ${OUT}/batch_bad.json "{\"jobs\": [\n")
expect_batch(${OUT}/batch_bad.json 2 "batch_bad.json: invalid JSON")
message("batch: ok")
