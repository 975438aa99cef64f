# The glTF fuzz target's build (tests/fuzz, a project of its own: libFuzzer needs clang, the main
# build uses GCC), when clang++ and its fuzzer runtime are installed (Debian: clang-14,
# libclang-rt-14-dev, in .ci/packages-full). Included from the top-level CMakeLists.txt before the
# engine: ninja starts ready steps in the order they are declared, so the fuzz build (about 50 s of
# one core that nothing else waits for) overlaps the engine's compile instead of running alone at
# the end of a from-scratch build. tests/CMakeLists.txt adds the fuzz.gltf test.
find_program(CANDELA_CLANGXX NAMES clang++-14 clang++)
set(CANDELA_FUZZ OFF)
if(CANDELA_CLANGXX)
  set(_probe ${CMAKE_BINARY_DIR}/fuzz-probe.cpp)
  file(WRITE ${_probe} "#include <cstddef>\n#include <cstdint>\nextern \"C\" int LLVMFuzzerTestOneInput(const std::uint8_t*, std::size_t) { return 0; }\n")
  execute_process(COMMAND ${CANDELA_CLANGXX} -fsanitize=fuzzer,address ${_probe} -o ${CMAKE_BINARY_DIR}/fuzz-probe
                  RESULT_VARIABLE _probe_result OUTPUT_QUIET ERROR_QUIET)
  if(_probe_result EQUAL 0)
    set(CANDELA_FUZZ ON)
  endif()
endif()
if(CANDELA_FUZZ)
  include(ExternalProject)
  ExternalProject_Add(fuzz_gltf_build
    SOURCE_DIR ${CMAKE_SOURCE_DIR}/tests/fuzz
    BINARY_DIR ${CMAKE_BINARY_DIR}/fuzz
    CMAKE_ARGS -G Ninja -DCMAKE_CXX_COMPILER=${CANDELA_CLANGXX} -DCMAKE_BUILD_TYPE=RelWithDebInfo
    INSTALL_COMMAND ""
    BUILD_ALWAYS ON)  # it compiles engine sources: let its own ninja decide what changed
else()
  message(STATUS "clang++ with libFuzzer not found: the fuzz.gltf test is not built (apt-get install clang-14 libclang-rt-14-dev)")
endif()
