# Profile-guided optimisation of the scw program (SCW_PGO; ON in the release preset).
#
# The build runs in three steps, all inside `cmake --build`:
#   1. an instrumented copy of scw (-fprofile-generate) is built in <build>/pgo/train, tests off;
#   2. it runs the training workload, `scw bench --evaluator` on the built-in default set (the
#      tuner's hot loop: plant, tyres, controllers, path matching; ~40 s), and writes its
#      profile to <build>/pgo/profile (preparation cache in <build>/pgo/cache, not the user's);
#   3. every target of this build compiles with that profile (-fprofile-use); code the training
#      did not run (tests, the MPC, Open-Car-Dynamics) compiles as without it.
# Steps 1-2 run once per build folder; after source changes the profile is stale for the changed
# functions (used where it still matches, ignored elsewhere: only speed, never results, depend on
# it). A fresh build folder trains anew.
#
# Results are bit for bit those of a build without it: the profile changes inlining, code layout
# and branch order, never the floating-point operations (-ffp-contract=off, no fast-math). The
# Magic Formula (plant/tire/magic_formula.cc) compiles without the profile: it is branch-free, ran
# slower with it, and GCC 12's tracer pass fails on its vector conditionals under -fprofile-use.
# Link-time optimisation on top measured about 3 % more, but GCC 12 then fails (an internal
# compiler error in its vector-conditional expansion) linking some test programs: not used.
# Measured: docs/scaling.md#throughput-per-core.

if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  message(FATAL_ERROR "SCW_PGO needs GCC (-fprofile-generate, -fprofile-use); "
                      "configure with -DSCW_PGO=OFF for ${CMAKE_CXX_COMPILER_ID}")
endif()
if(CMAKE_CXX_FLAGS MATCHES "-fsanitize|-fprofile")
  message(FATAL_ERROR "SCW_PGO cannot be combined with the sanitizers or other profiling flags "
                      "in CMAKE_CXX_FLAGS; configure with -DSCW_PGO=OFF")
endif()

include(ExternalProject)
set(SCW_PGO_DIR "${CMAKE_BINARY_DIR}/pgo")
set(SCW_PGO_TRAIN_DIR "${SCW_PGO_DIR}/train")
set(SCW_PGO_PROFILE_DIR "${SCW_PGO_DIR}/profile")
# The profile files are named after the object files relative to their build folder, so that the
# training build's names match this build's.
set(_scw_pgo_generate
    "-fprofile-generate=${SCW_PGO_PROFILE_DIR} -fprofile-update=atomic -fprofile-prefix-path=${SCW_PGO_TRAIN_DIR}")
ExternalProject_Add(
  scw_pgo_profile
  SOURCE_DIR "${PROJECT_SOURCE_DIR}"
  BINARY_DIR "${SCW_PGO_TRAIN_DIR}"
  STAMP_DIR "${SCW_PGO_DIR}/stamp"
  TMP_DIR "${SCW_PGO_DIR}/tmp"
  CMAKE_ARGS
    -DCMAKE_BUILD_TYPE=${CMAKE_BUILD_TYPE}
    -DCMAKE_CXX_COMPILER=${CMAKE_CXX_COMPILER}
    "-DCMAKE_CXX_FLAGS=${CMAKE_CXX_FLAGS} ${_scw_pgo_generate}"
    "-DCMAKE_EXE_LINKER_FLAGS=${CMAKE_EXE_LINKER_FLAGS} -fprofile-generate=${SCW_PGO_PROFILE_DIR}"
    -DSCW_PGO=OFF
    -DSCW_BUILD_TESTS=OFF
    -DSCW_WERROR=OFF
    -DSCW_WITH_MPI=${SCW_WITH_MPI}
    -DSCW_TCMALLOC=${SCW_TCMALLOC}
    -DSCW_WITH_OCD=${SCW_WITH_OCD}
    "-DSCW_OCD_SOURCE_DIR=${SCW_OCD_SOURCE_DIR}"
  BUILD_COMMAND ${CMAKE_COMMAND} --build <BINARY_DIR> --target scw
  INSTALL_COMMAND
    ${CMAKE_COMMAND} -E rm -rf "${SCW_PGO_PROFILE_DIR}"
    COMMAND ${CMAKE_COMMAND} -E env "SCW_CACHE_DIR=${SCW_PGO_DIR}/cache"
      <BINARY_DIR>/tuning/scw bench --evaluator --evaluations 2 --repeat 1
  USES_TERMINAL_INSTALL ON)

add_compile_options(
  "-fprofile-use=${SCW_PGO_PROFILE_DIR}" "-fprofile-prefix-path=${CMAKE_BINARY_DIR}"
  -fprofile-partial-training -Wno-missing-profile -Wno-coverage-mismatch)

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
  scw_pgo_targets_under("${PROJECT_SOURCE_DIR}" targets)
  foreach(t IN LISTS targets)
    get_target_property(type ${t} TYPE)
    if(type MATCHES "^(STATIC_LIBRARY|SHARED_LIBRARY|OBJECT_LIBRARY|EXECUTABLE)$")
      add_dependencies(${t} scw_pgo_profile)
    endif()
  endforeach()
endfunction()
