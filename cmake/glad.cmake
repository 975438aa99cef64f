# Generates the OpenGL 4.5 core loader with Debian's python3-glad at configure time, into the
# build tree. Debian's python3 is used explicitly: another python3 may be first on PATH.
set(CANDELA_GLAD_DIR "${CMAKE_BINARY_DIR}/glad")
set(CANDELA_GLAD_EXTENSIONS "GL_KHR_debug,GL_ARB_clip_control")
find_program(CANDELA_SYSTEM_PYTHON NAMES python3 PATHS /usr/bin NO_DEFAULT_PATH)
if(NOT CANDELA_SYSTEM_PYTHON)
  message(FATAL_ERROR "Debian's /usr/bin/python3 is needed to run python3-glad (apt-get install python3-glad)")
endif()
set(_glad_stamp "${CANDELA_GLAD_DIR}/stamp-${CANDELA_GLAD_EXTENSIONS}")
if(NOT EXISTS "${_glad_stamp}")
  file(REMOVE_RECURSE "${CANDELA_GLAD_DIR}")
  execute_process(
    COMMAND ${CANDELA_SYSTEM_PYTHON} -m glad --quiet --reproducible --api gl:core=4.5
            --extensions ${CANDELA_GLAD_EXTENSIONS} --out-path ${CANDELA_GLAD_DIR} c
    RESULT_VARIABLE _glad_result OUTPUT_VARIABLE _glad_out ERROR_VARIABLE _glad_out)
  if(NOT _glad_result EQUAL 0)
    message(FATAL_ERROR "glad generation failed (is python3-glad installed?):\n${_glad_out}")
  endif()
  file(WRITE "${_glad_stamp}" "")
endif()
add_library(candela_glad STATIC "${CANDELA_GLAD_DIR}/src/gl.c")
target_include_directories(candela_glad SYSTEM PUBLIC $<BUILD_INTERFACE:${CANDELA_GLAD_DIR}/include>)
# Installed with the engine's headers (<prefix>/include/candela/glad, KHR), which include glad/gl.h;
# an imported target's include directories are system ones for its users anyway.
target_include_directories(candela_glad PUBLIC $<INSTALL_INTERFACE:include/candela>)
set_target_properties(candela_glad PROPERTIES POSITION_INDEPENDENT_CODE ON)
