# SPDX-License-Identifier: MIT
# Reliability builds (see docs/RELIABILITY.md). Included from the top-level CMakeLists.txt before
# any target is defined, so the flags reach every target, tests included.
#
#   DEEPCUT_SANITIZE=ON  AddressSanitizer + UndefinedBehaviorSanitizer (gcc or clang); any report
#                        aborts the process, so a test that triggers one fails.
#                        scripts/sanitize.sh configures build-asan with it and runs ctest there.
#   DEEPCUT_FUZZ=ON      libFuzzer targets under tests/fuzz (clang only), CTest label `fuzz`,
#                        which the default test run never builds. Implies ASan + UBSan and
#                        coverage instrumentation of everything. scripts/fuzz.sh runs them.
option(DEEPCUT_SANITIZE "Build with AddressSanitizer and UndefinedBehaviorSanitizer" OFF)
option(DEEPCUT_FUZZ "Build the libFuzzer targets (clang only; CTest label fuzz)" OFF)
set(DEEPCUT_FUZZ_SECONDS 60 CACHE STRING "How long each fuzz target runs in its CTest test")

set(DEEPCUT_SANITIZER_FLAGS -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)

if(DEEPCUT_FUZZ AND NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(WARNING "DEEPCUT_FUZZ needs clang (libFuzzer); the fuzz targets are not built. "
                  "Configure with -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++.")
  set(DEEPCUT_FUZZ OFF CACHE BOOL "" FORCE)
endif()

if(DEEPCUT_FUZZ)
  add_compile_options(${DEEPCUT_SANITIZER_FLAGS} -fsanitize=fuzzer-no-link -g)
  add_link_options(-fsanitize=address,undefined)
elseif(DEEPCUT_SANITIZE)
  add_compile_options(${DEEPCUT_SANITIZER_FLAGS} -g)
  add_link_options(-fsanitize=address,undefined)
endif()
