# How fast the project compiles (docs/building.md): ccache when installed, precompiled third-party
# headers per target, and where -O3 goes. Included by the root CMakeLists.txt before any target.

# ccache, when installed and no launcher was chosen: -DMTCAL_CCACHE=OFF (or CCACHE_DISABLE=1 in the
# environment, as the timing runs do) compiles without it. Units built with a precompiled header are
# cached only with these sloppiness settings (ccache manual, "Precompiled headers"): a launcher that
# is ccache itself, given by the user, gets them too.
option(MTCAL_CCACHE "Compile through ccache when it is installed" ON)
# OFF by default: with GCC 12 it measured no faster here (docs/building.md, "Precompiled headers").
option(MTCAL_PCH "Precompile the heavy third-party headers (Eigen, nlohmann-json, CLI11, fmt, GoogleTest, pybind11, Google Benchmark) per target" OFF)
set(MTCAL_CCACHE_SLOPPINESS pch_defines,time_macros,include_file_mtime,include_file_ctime)
foreach(lang CXX C)
  if(NOT CMAKE_${lang}_COMPILER_LAUNCHER AND MTCAL_CCACHE)
    find_program(MTCAL_CCACHE_PROGRAM ccache)
    if(MTCAL_CCACHE_PROGRAM)
      set(CMAKE_${lang}_COMPILER_LAUNCHER ${MTCAL_CCACHE_PROGRAM})
    endif()
  endif()
  set(launcher "${CMAKE_${lang}_COMPILER_LAUNCHER}")
  list(LENGTH launcher n)
  if(n EQUAL 1 AND MTCAL_PCH)
    cmake_path(GET launcher FILENAME name)
    if(name STREQUAL "ccache")
      set(CMAKE_${lang}_COMPILER_LAUNCHER ${CMAKE_COMMAND} -E env CCACHE_SLOPPINESS=${MTCAL_CCACHE_SLOPPINESS} ${launcher})
    endif()
  endif()
endforeach()
if(CMAKE_CXX_COMPILER_LAUNCHER)
  list(GET CMAKE_CXX_COMPILER_LAUNCHER -1 _mtcal_launcher)
  message(STATUS "Compiler launcher: ${_mtcal_launcher}")
else()
  message(STATUS "Compiler launcher: none (Debian: apt-get install ccache, or scripts/install-deps)")
endif()

# Precompiled headers: each target precompiles the third-party and standard headers most of its units
# include (a precompiled header is private to its target, never propagated: a header that forgets an
# include still fails in tests/headers and in the builds without it, the sanitizer presets). A file
# compiled with its own options (-O3, -fno-math-errno, ...) cannot use the target's header: it is
# skipped (mtcal_no_pch).
function(mtcal_precompile_headers target)
  if(MTCAL_PCH)
    target_precompile_headers(${target} PRIVATE ${ARGN})
  endif()
endfunction()
function(mtcal_no_pch)
  set_source_files_properties(${ARGN} DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR} PROPERTIES SKIP_PRECOMPILE_HEADERS ON)
endfunction()

# The standard headers nearly every unit includes.
set(MTCAL_PCH_STD <algorithm> <array> <cmath> <cstddef> <functional> <limits> <map> <memory> <optional>
    <span> <stdexcept> <string> <string_view> <utility> <vector>)

# The compile-time check's yardstick (tests/buildtime/baseline.cpp; scripts/build-times): the same
# unit compiled as three object libraries, each in its own build folder added at the start, the middle
# and the end of the build, so that Ninja (which starts ready commands in the order of build.ninja)
# compiles them at different times of it; fixed flags, no ccache, no precompiled header.
function(mtcal_build_baseline suffix)
  if(MTCAL_BUILD_TESTS)
    set(MTCAL_BUILD_BASELINE_SUFFIX ${suffix})
    add_subdirectory(${PROJECT_SOURCE_DIR}/tests/buildtime ${PROJECT_BINARY_DIR}/buildtime_${suffix})
  endif()
endfunction()

# Which headers each target precompiles (with MTCAL_PCH=ON). Called once every target exists, so
# that no source list changes; the files compiled with their own options are named here.
function(mtcal_apply_pch)
  if(NOT MTCAL_PCH)
    return()
  endif()
  mtcal_precompile_headers(mtcal_core ${MTCAL_PCH_STD} <Eigen/Core> <Eigen/Geometry> <fmt/format.h>
                           <nlohmann/json.hpp>)
  mtcal_own_option_sources(own_options)
  set_source_files_properties(${own_options} DIRECTORY ${PROJECT_SOURCE_DIR}/src PROPERTIES SKIP_PRECOMPILE_HEADERS ON)
  mtcal_precompile_headers(mtcal ${MTCAL_PCH_STD} <CLI/CLI.hpp> <Eigen/Core> <fmt/format.h> <nlohmann/json.hpp>)
  if(TARGET mtcal_tests)
    mtcal_precompile_headers(mtcal_tests ${MTCAL_PCH_STD} <gtest/gtest.h> <Eigen/Core> <Eigen/Geometry>
                             <fmt/format.h> <nlohmann/json.hpp>)
    set_source_files_properties(${PROJECT_SOURCE_DIR}/tests/kinematics/test_kernel_isa.cpp
      DIRECTORY ${PROJECT_SOURCE_DIR}/tests PROPERTIES SKIP_PRECOMPILE_HEADERS ON)
  endif()
  if(TARGET mtcal_bench)
    mtcal_precompile_headers(mtcal_bench ${MTCAL_PCH_STD} <benchmark/benchmark.h> <Eigen/Core>)
    set_source_files_properties(${PROJECT_SOURCE_DIR}/bench/bench_error_model.cpp
      DIRECTORY ${PROJECT_SOURCE_DIR}/bench PROPERTIES SKIP_PRECOMPILE_HEADERS ON)
  endif()
  if(TARGET mtcal_python)
    mtcal_precompile_headers(mtcal_python <pybind11/pybind11.h> <pybind11/numpy.h> <pybind11/stl.h>
                             ${MTCAL_PCH_STD} <Eigen/Core>)
  endif()
endfunction()

# Unity (jumbo) builds: each target's units compiled in batches of MTCAL_UNITY_BATCH, so that the
# heavy headers (Eigen, nlohmann-json, CLI11, GoogleTest, pybind11) are parsed, and their common
# templates instantiated, once per batch instead of once per unit (docs/building.md, "Unity builds").
# A unit compiled with its own options (-O3, -ffp-contract=off, ...) stays alone: its options must not
# reach the units of a batch, nor theirs it. MTCAL_UNITY_BATCH balances the saving against the two
# cores Ninja keeps busy and against incremental builds (touching one unit recompiles its batch).
option(MTCAL_UNITY "Compile each target's units in unity batches (faster full builds, slower single-unit rebuilds)" OFF)
set(MTCAL_UNITY_BATCH 8 CACHE STRING "Units per unity batch (MTCAL_UNITY=ON)")
function(mtcal_apply_unity)
  if(NOT MTCAL_UNITY)
    return()
  endif()
  # The library, the server, the command, the Python module, the benchmarks and the tests' targets
  # (tests/CMakeLists.txt; not tests/headers, whose units must each compile alone). A test unit's
  # helpers in its anonymous namespace carry names of their own (the shared ones are in
  # tests/testing/examples.hpp): two units of a batch are one translation unit.
  get_property(test_targets DIRECTORY ${PROJECT_SOURCE_DIR}/tests PROPERTY BUILDSYSTEM_TARGETS)
  foreach(target mtcal_core mtcal_server mtcal mtcal_python mtcal_bench ${test_targets})
    if(TARGET ${target})
      set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE ${MTCAL_UNITY_BATCH})
      # GCC 12 inlines across the units of a batch and then reports -Wmaybe-uninitialized on
      # std::string members of default-constructed records (history/analysis.cpp's ParameterChange
      # in a batch): a false positive the separate units do not give. The default build keeps the
      # warning. -Wsubobject-linkage is for headers (a class of a header with a member of a type from
      # an anonymous namespace differs in every unit that includes it); in a batch every unit is an
      # included file, and a unit's own class with a member of its own anonymous type (server.cpp's
      # Impl) is what it warns of.
      target_compile_options(${target} PRIVATE $<$<CXX_COMPILER_ID:GNU>:-Wno-maybe-uninitialized -Wno-subobject-linkage>)
    endif()
  endforeach()
  mtcal_own_option_sources(own)
  set_source_files_properties(${own} DIRECTORY ${PROJECT_SOURCE_DIR}/src PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
endfunction()

# The library's units compiled with their own options (-O3 on the hot code, -ffp-contract=off, ...):
# neither a target's precompiled header nor a unity batch may take them.
function(mtcal_own_option_sources out)
  set(own kinematics/batch.cpp kinematics/chain.cpp kinematics/error_model.cpp kinematics/first_order.cpp
      kinematics/kernel_isa.cpp kinematics/transform.cpp model/motion_function.cpp evaluation/volumetric.cpp
      evaluation/volumetric_stream.cpp evaluation/error_stream.cpp evaluation/toolpath.cpp probing/rotary_axis.cpp
      fitting/least_squares.cpp)
  list(TRANSFORM own PREPEND ${PROJECT_SOURCE_DIR}/src/)
  set(${out} ${own} PARENT_SCOPE)
endfunction()

# -O3 only on the hot code (docs/performance.md: the error kernels, the scalar chain and motion forms
# they reproduce, the grid/volumetric/toolpath streams), -O2 elsewhere in Release: it compiles faster
# and the benchmarks measured no slower (docs/building.md, "-O2 outside the hot code").
# MTCAL_O3_EVERYWHERE=ON restores -O3 for every unit.
option(MTCAL_O3_EVERYWHERE "Release: -O3 for every unit (default: -O3 only on the hot code, -O2 elsewhere)" OFF)
if(NOT MTCAL_O3_EVERYWHERE)
  string(REPLACE "-O3" "-O2" CMAKE_CXX_FLAGS_RELEASE "${CMAKE_CXX_FLAGS_RELEASE}")
endif()
function(mtcal_apply_hot_o3)
  if(MTCAL_O3_EVERYWHERE OR NOT CMAKE_BUILD_TYPE STREQUAL "Release")
    return()
  endif()
  # The list: the kernels and streams of docs/performance.md, and the rotary-axis estimators
  # (probing/rotary_axis.cpp, fitting/least_squares.cpp), measured 9-13 % slower at -O2
  # (BM_Triples_360, BM_LeastSquares_360).
  mtcal_own_option_sources(hot)
  # Appended: batch.cpp and volumetric.cpp keep their own options (-ffp-contract=off, ...).
  set_property(SOURCE ${hot} DIRECTORY ${PROJECT_SOURCE_DIR}/src APPEND PROPERTY COMPILE_OPTIONS -O3)
endfunction()

# The tests' `python3`: the shell and Python test scripts start it several hundred times in all. A
# version manager's shim first on PATH (pyenv's is a bash script that execs pyenv) costs about 0.5
# CPU-seconds a start on this project's machines, against 0.03 s for the interpreter itself, and
# its interpreter may lack Debian's python3-numpy and friends (the packages scripts/install-deps
# installs belong to Debian's interpreter). The tests of the directory that calls this get a PATH
# that starts with a folder holding one `python3`, Debian's /usr/bin/python3; nothing changes where
# that does not exist. (CMake 3.25 sets test properties only in the directory that made the tests.)
function(mtcal_tests_use_debian_python)
  find_program(MTCAL_TEST_PYTHON3 NAMES python3 PATHS /usr/bin NO_DEFAULT_PATH)
  if(NOT MTCAL_TEST_PYTHON3)
    return()
  endif()
  set(dir ${PROJECT_BINARY_DIR}/test-python)
  if(NOT EXISTS ${dir}/python3)
    file(MAKE_DIRECTORY ${dir})
    file(CREATE_LINK ${MTCAL_TEST_PYTHON3} ${dir}/python3 SYMBOLIC)
  endif()
  get_property(tests DIRECTORY PROPERTY TESTS)
  if(tests)
    set_property(TEST ${tests} APPEND PROPERTY ENVIRONMENT_MODIFICATION PATH=path_list_prepend:${dir})
  endif()
endfunction()
