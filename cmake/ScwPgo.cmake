# Profile-guided optimisation of the scw program (SCW_PGO; ON in the release preset), and
# link-time optimisation of it on top (SCW_LTO; ON in the release preset too).
#
# The build runs in up to four steps, all inside `cmake --build`:
#   1. an instrumented copy of scw (-fprofile-generate) is built in <build>/pgo/train, tests off;
#   2. it runs the training workload, `scw bench --evaluator` on the built-in default set (the
#      tuner's hot loop: plant, tyres, controllers, path matching; ~40 s), and writes its
#      profile to <build>/pgo/profile (preparation cache in <build>/pgo/cache, not the user's);
#   3. every target of this build compiles with that profile (-fprofile-use); code the training
#      did not run (tests, the MPC, Open-Car-Dynamics) compiles as without it;
#   4. with SCW_LTO, a second stage in <build>/pgo/lto builds scw alone once more, with the same
#      profile and -flto (its libraries as link-time objects), and that program replaces this
#      build's scw (<build>/tuning/scw) at the end of every build. The test programs keep the
#      step-3 libraries: GCC 12 fails (an internal compiler error in its vector-conditional
#      expansion) linking some of them with -flto, and an -flto link per test program would
#      multiply the build time. The golden tests run the replaced scw.
# Steps 1-2 run once per build folder; after source changes the profile is stale for the changed
# functions (used where it still matches, ignored elsewhere: only speed, never results, depend on
# it). A fresh build folder trains anew. Step 4 follows every source change (its own build
# folder, incremental) and costs about as much as step 1 from scratch.
#
# Results are bit for bit those of a build without it: the profile and the link-time inlining
# change inlining, code layout and branch order, never the floating-point operations
# (-ffp-contract=off, no fast-math). The Magic Formula (plant/tire/magic_formula.cc) compiles
# without the profile: it is branch-free, ran slower with it, and GCC 12's tracer pass fails on
# its vector conditionals under -fprofile-use.
# Measured: docs/scaling.md#throughput-per-core.
#
# SCW_PGO_PROFILE (set by step 4 for its stage, not by users): compile with that profile and
# train nothing.

if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  message(FATAL_ERROR "SCW_PGO needs GCC (-fprofile-generate, -fprofile-use); "
                      "configure with -DSCW_PGO=OFF for ${CMAKE_CXX_COMPILER_ID}")
endif()
if(CMAKE_CXX_FLAGS MATCHES "-fsanitize|-fprofile")
  message(FATAL_ERROR "SCW_PGO cannot be combined with the sanitizers or other profiling flags "
                      "in CMAKE_CXX_FLAGS; configure with -DSCW_PGO=OFF")
endif()

# The profile's file names follow the object files relative to their build folder, so that the
# training build's names match this build's (-fprofile-prefix-path).
set(_scw_pgo_use
    -fprofile-partial-training -Wno-missing-profile -Wno-coverage-mismatch
    "-fprofile-prefix-path=${CMAKE_BINARY_DIR}")
if(NOT SCW_PGO)  # a stage given a profile (step 4)
  add_compile_options("-fprofile-use=${SCW_PGO_PROFILE}" ${_scw_pgo_use})
  function(scw_pgo_finish)
  endfunction()
  return()
endif()
if(SCW_PGO_PROFILE)
  message(FATAL_ERROR "SCW_PGO trains its own profile; leave SCW_PGO_PROFILE empty")
endif()

include(ExternalProject)
set(SCW_PGO_DIR "${CMAKE_BINARY_DIR}/pgo")
set(SCW_PGO_TRAIN_DIR "${SCW_PGO_DIR}/train")
set(SCW_PGO_PROFILE_DIR "${SCW_PGO_DIR}/profile")
# What both stages build: scw alone, with this build's compiler, build type and features.
set(_scw_stage_args
    -DCMAKE_BUILD_TYPE=${CMAKE_BUILD_TYPE}
    -DCMAKE_CXX_COMPILER=${CMAKE_CXX_COMPILER}
    -DSCW_PGO=OFF
    -DSCW_LTO=OFF
    -DSCW_BUILD_TESTS=OFF
    -DSCW_WERROR=OFF
    -DSCW_WITH_MPI=${SCW_WITH_MPI}
    -DSCW_TCMALLOC=${SCW_TCMALLOC}
    -DSCW_WITH_OCD=${SCW_WITH_OCD}
    "-DSCW_OCD_SOURCE_DIR=${SCW_OCD_SOURCE_DIR}")
set(_scw_pgo_generate
    "-fprofile-generate=${SCW_PGO_PROFILE_DIR} -fprofile-update=atomic -fprofile-prefix-path=${SCW_PGO_TRAIN_DIR}")
ExternalProject_Add(
  scw_pgo_profile
  SOURCE_DIR "${PROJECT_SOURCE_DIR}"
  BINARY_DIR "${SCW_PGO_TRAIN_DIR}"
  STAMP_DIR "${SCW_PGO_DIR}/stamp"
  TMP_DIR "${SCW_PGO_DIR}/tmp"
  CMAKE_ARGS
    ${_scw_stage_args}
    "-DCMAKE_CXX_FLAGS=${CMAKE_CXX_FLAGS} ${_scw_pgo_generate}"
    "-DCMAKE_EXE_LINKER_FLAGS=${CMAKE_EXE_LINKER_FLAGS} -fprofile-generate=${SCW_PGO_PROFILE_DIR}"
  BUILD_COMMAND ${CMAKE_COMMAND} --build <BINARY_DIR> --target scw
  INSTALL_COMMAND
    ${CMAKE_COMMAND} -E rm -rf "${SCW_PGO_PROFILE_DIR}"
    COMMAND ${CMAKE_COMMAND} -E env "SCW_CACHE_DIR=${SCW_PGO_DIR}/cache"
      <BINARY_DIR>/tuning/scw bench --evaluator --evaluations 2 --repeat 1
  USES_TERMINAL_INSTALL ON)

add_compile_options("-fprofile-use=${SCW_PGO_PROFILE_DIR}" ${_scw_pgo_use})

if(SCW_LTO)
  set(SCW_LTO_DIR "${SCW_PGO_DIR}/lto")
  ExternalProject_Add(
    scw_lto
    SOURCE_DIR "${PROJECT_SOURCE_DIR}"
    BINARY_DIR "${SCW_LTO_DIR}"
    STAMP_DIR "${SCW_PGO_DIR}/lto-stamp"
    TMP_DIR "${SCW_PGO_DIR}/tmp"
    CMAKE_ARGS
      ${_scw_stage_args}
      "-DCMAKE_CXX_FLAGS=${CMAKE_CXX_FLAGS}"
      "-DCMAKE_EXE_LINKER_FLAGS=${CMAKE_EXE_LINKER_FLAGS}"
      -DCMAKE_INTERPROCEDURAL_OPTIMIZATION=ON
      "-DSCW_PGO_PROFILE=${SCW_PGO_PROFILE_DIR}"
    BUILD_COMMAND ${CMAKE_COMMAND} --build <BINARY_DIR> --target scw
    BUILD_ALWAYS ON
    INSTALL_COMMAND ""
    DEPENDS scw_pgo_profile
    USES_TERMINAL_BUILD ON)
endif()

# After the targets exist: every one of them waits for the profile.
function(scw_pgo_targets_under dir out)
  get_property(targets DIRECTORY "${dir}" PROPERTY BUILDSYSTEM_TARGETS)
  get_property(subdirs DIRECTORY "${dir}" PROPERTY SUBDIRECTORIES)
  foreach(sub IN LISTS subdirs)
    scw_pgo_targets_under("${sub}" more)
    list(APPEND targets ${more})
  endforeach()
  set(${out} ${targets} PARENT_SCOPE)
endfunction()

function(scw_pgo_finish)
  if(SCW_LTO)
    # Step 4's program replaces this build's scw once both exist (every build; a copy only).
    add_custom_target(scw_lto_install ALL
      COMMAND ${CMAKE_COMMAND} -E copy "${SCW_LTO_DIR}/tuning/scw" "$<TARGET_FILE:scw>"
      COMMENT "scw: the link-time optimised program (SCW_LTO) replaces tuning/scw")
    add_dependencies(scw_lto_install scw scw_lto)
  endif()
  scw_pgo_targets_under("${PROJECT_SOURCE_DIR}" targets)
  foreach(t IN LISTS targets)
    get_target_property(type ${t} TYPE)
    if(type MATCHES "^(STATIC_LIBRARY|SHARED_LIBRARY|OBJECT_LIBRARY|EXECUTABLE)$")
      add_dependencies(${t} scw_pgo_profile)
    endif()
  endforeach()
endfunction()
