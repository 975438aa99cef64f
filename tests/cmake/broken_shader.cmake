# A copy of shaders/ with a syntax error in an included file: `candela shaders check` and
# `candela render` must fail (exit 1) naming that file and line, not the file that includes it.
#   cmake -DCANDELA=... -DSHADERS=... -DWORK=... -DSCENE=... -P broken_shader.cmake
file(REMOVE_RECURSE ${WORK})
file(COPY ${SHADERS}/ DESTINATION ${WORK})
file(READ ${WORK}/lighting/shading.glsl text)
# A call with the wrong type on a line of its own (a semantic error: Mesa loses the file there).
string(REPLACE "vec3 environment_irradiance(vec3 n) {" "vec3 environment_irradiance(vec3 n) {\n    float broken = saturate(vec2(1.0));" text "${text}")
file(WRITE ${WORK}/lighting/shading.glsl "${text}")
string(FIND "${text}" "    float broken = saturate(vec2(1.0));" at)
string(SUBSTRING "${text}" 0 ${at} before)
string(REGEX MATCHALL "\n" newlines "${before}")
list(LENGTH newlines count)
math(EXPR line "${count} + 1")
foreach(cmd "shaders;check;--shader-dir;${WORK}" "render;${SCENE};-o;${WORK}/x.png;--size;16x16;--shader-dir;${WORK}")
  execute_process(COMMAND ${CANDELA} ${cmd} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
  message("candela ${cmd}: exit ${code}\n${out}${err}")
  if(NOT code EQUAL 1)
    message(FATAL_ERROR "expected exit code 1, got ${code}")
  endif()
  if(NOT "${out}${err}" MATCHES "lighting/shading.glsl:${line}:")
    message(FATAL_ERROR "the message does not name lighting/shading.glsl:${line}")
  endif()
endforeach()
