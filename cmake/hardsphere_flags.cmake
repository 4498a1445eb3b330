# hardsphere_build_flags: the compile options of this project's own targets, linked PRIVATE by
# each of them, so nothing is forced on a project that embeds this one.
# Never -ffast-math: "no contact" is +inf and NaN checks must stay meaningful.
add_library(hardsphere_build_flags INTERFACE)
target_compile_features(hardsphere_build_flags INTERFACE cxx_std_17)
# -ffp-contract=off: no fused multiply-adds the source does not spell, so a native build gives the
# portable build's results bit for bit, and moving code between files or functions (which changes
# what the compiler inlines and fuses) cannot change a run.
target_compile_options(hardsphere_build_flags INTERFACE -Wall -Wextra -ffp-contract=off)
if(HS_NATIVE)
  target_compile_options(hardsphere_build_flags INTERFACE -march=native)
endif()
if(HS_BUILD_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "HS_BUILD_FUZZ needs clang (libFuzzer): -DCMAKE_CXX_COMPILER=clang++-14, or run scripts/fuzz.sh")
  endif()
  # Everything instrumented for coverage and checked by ASan/UBSan; UB aborts (a finding).
  target_compile_options(hardsphere_build_flags INTERFACE -fsanitize=fuzzer-no-link,address,undefined
                         -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g)
  target_link_options(hardsphere_build_flags INTERFACE -fsanitize=address,undefined)
endif()
