# Installing Candela (`cmake --install build --prefix P`) and packaging it (`cpack -G DEB` in the
# build directory). docs/install.md describes the result; tests/install/install_test.sh checks it.
#
# <prefix>/bin/candela                       the command (the viewer is `candela view`, in it)
# <prefix>/lib/libcandela_image_io.so        OpenImageIO module, found beside bin/ (image/image_io.cpp)
# <prefix>/share/candela/shaders/            the shared GLSL          } found from the executable:
# <prefix>/share/candela/{effects,gpu}/      each effect's GLSL and   } <exe>/../share/candela
#                                            the blocks C++ shares    } (shader/shader_library.hpp)
# <prefix>/share/candela/samples/scenes/     the sample scenes (`candela bench accuracy` renders them)
# <prefix>/share/doc/candela/                third_party_notes
# <prefix>/lib/libcandela.a, libcandela_glad.a, include/candela/    the engine (Candela::engine)
# <prefix>/lib/cmake/Candela/                find_package(Candela CONFIG), candela_add_golden_test()
#
# Two components, one Debian package each: `runtime` (candela: the command and its data) and
# `development` (libcandela-dev: the library, headers and CMake package; it depends on candela,
# whose executable the CMake package exports as Candela::candela).
include(CMakePackageConfigHelpers)

set(CANDELA_INSTALL_CMAKEDIR lib/cmake/Candela)
set(CANDELA_INSTALL_DATADIR share/candela)

# --- runtime: the command, the image I/O module, shaders, sample scenes, notices ---
set_target_properties(candela_cli PROPERTIES EXPORT_NAME candela)
install(TARGETS candela_cli EXPORT CandelaTargets RUNTIME DESTINATION bin COMPONENT runtime)
if(TARGET candela_image_io)
  install(TARGETS candela_image_io LIBRARY DESTINATION lib COMPONENT runtime)
endif()
install(DIRECTORY ${CMAKE_SOURCE_DIR}/shaders/ DESTINATION ${CANDELA_INSTALL_DATADIR}/shaders COMPONENT runtime)
# The effects' GLSL lives beside their C++ (engine/effects/NAME/) and includes the blocks that C++
# and GLSL share (engine/gpu/*.h), by the same names as in the source tree ("effects/ssao/ssao_data.h").
# Only shader sources are copied; `candela shaders check` (run on the installed command by
# tests/install/install_test.sh) builds every program, so a shader left out fails the test.
install(DIRECTORY ${CMAKE_SOURCE_DIR}/engine/effects ${CMAKE_SOURCE_DIR}/engine/gpu
        DESTINATION ${CANDELA_INSTALL_DATADIR} COMPONENT runtime
        FILES_MATCHING PATTERN "*.glsl" PATTERN "*.vert" PATTERN "*.frag" PATTERN "*.comp" PATTERN "*.geom"
                       PATTERN "*.tesc" PATTERN "*.tese" PATTERN "*.h"
                       PATTERN "ltc_fit" EXCLUDE)
file(GLOB _candela_sample_files ${CMAKE_SOURCE_DIR}/samples/scenes/*.gltf ${CMAKE_SOURCE_DIR}/samples/scenes/*.bin
     ${CMAKE_SOURCE_DIR}/samples/scenes/*.png)
install(FILES ${_candela_sample_files} DESTINATION ${CANDELA_INSTALL_DATADIR}/samples/scenes COMPONENT runtime)
install(FILES ${CMAKE_SOURCE_DIR}/third_party_notes DESTINATION share/doc/candela COMPONENT runtime)

# --- development: the engine library, its headers, glad, the CMake package ---
set_target_properties(candela PROPERTIES EXPORT_NAME engine)
set_target_properties(candela_glad PROPERTIES EXPORT_NAME glad)
install(TARGETS candela candela_glad EXPORT CandelaTargets ARCHIVE DESTINATION lib COMPONENT development)
# Under include/candela/ with the source tree's folders (#include "scene/gltf_loader.hpp"), and the
# generated GL loader the headers include (glad/gl.h, KHR/khrplatform.h).
install(DIRECTORY ${CMAKE_SOURCE_DIR}/engine/ DESTINATION include/candela COMPONENT development
        FILES_MATCHING PATTERN "*.hpp" PATTERN "*.h" PATTERN "ltc_fit" EXCLUDE)
install(DIRECTORY ${CANDELA_GLAD_DIR}/include/ DESTINATION include/candela COMPONENT development)
install(EXPORT CandelaTargets NAMESPACE Candela:: DESTINATION ${CANDELA_INSTALL_CMAKEDIR} COMPONENT development)
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/package/CandelaConfig.cmake.in
                              ${CMAKE_BINARY_DIR}/package/CandelaConfig.cmake
                              INSTALL_DESTINATION ${CANDELA_INSTALL_CMAKEDIR} PATH_VARS CANDELA_INSTALL_DATADIR)
# 0.x: a minor release may change the API, so only the same major.minor is compatible.
write_basic_package_version_file(${CMAKE_BINARY_DIR}/package/CandelaConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/package/CandelaConfig.cmake ${CMAKE_BINARY_DIR}/package/CandelaConfigVersion.cmake
              ${CMAKE_SOURCE_DIR}/cmake/package/CandelaGoldenTest.cmake
              ${CMAKE_SOURCE_DIR}/cmake/package/candela_golden_check.cmake
        DESTINATION ${CANDELA_INSTALL_CMAKEDIR} COMPONENT development)

# --- cpack -G DEB ---
set(CANDELA_PACKAGE_MAINTAINER "Candela maintainers <maintainers@candela.invalid>"
    CACHE STRING "The Maintainer field of the Debian packages")
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME candela)
set(CPACK_PACKAGE_VENDOR "Candela")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "${CANDELA_PACKAGE_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${CANDELA_PACKAGE_MAINTAINER}")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL runtime development)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME candela)
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_NAME libcandela-dev)
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_SECTION libdevel)
# Each package's first line is its Debian synopsis (no CPACK_PACKAGE_DESCRIPTION_SUMMARY: CPack
# would put that one line before both).
set(CPACK_COMPONENT_RUNTIME_DESCRIPTION "Candela: OpenGL 4.5 glTF renderer, the candela command and its shaders\n\
Renders glTF 2.0 scenes offscreen (EGL, or OSMesa) or in a window, ray traces references, compares images.")
set(CPACK_COMPONENT_DEVELOPMENT_DESCRIPTION "Candela: OpenGL 4.5 glTF renderer, the engine library and CMake package\n\
find_package(Candela CONFIG) gives Candela::engine, Candela::candela and candela_add_golden_test().")
# The runtime package's Depends come from the shared libraries its ELF files link, through
# dpkg-shlibdeps (dpkg-dev): libc6, libstdc++6, libegl1, libosmesa6, libglfw3, libpng16-16,
# libglslang, libmeshoptimizer, ... and, for the image module, libopenimageio. What the link does not
# show: EGL's llvmpipe is a DRI driver (libgl1-mesa-dri), loaded by Mesa's EGL vendor; without it
# `--backend auto` still renders through OSMesa, so it is a Recommends.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_RECOMMENDS "libgl1-mesa-dri")
# The development package holds a static library and headers, which dpkg-shlibdeps cannot see
# through: its Depends are the -dev packages of what CandelaConfig.cmake finds (find_dependency)
# and the static library's link interface names, listed here by hand.
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_DEPENDS
    "candela (= ${PROJECT_VERSION}), cmake (>= 3.25), pkg-config, libegl-dev, libosmesa6-dev, libstb-dev, libglfw3-dev, libglm-dev, libtinygltf-dev, nlohmann-json3-dev, glslang-dev, libpng-dev, libdraco-dev, libmeshoptimizer-dev")
include(CPack)
