# Installed headers must not depend on the consumer's ISA flags (-march): no intrinsics, no
# ISA macros. Run as: cmake -DPREFIX=<install prefix> -P check_installed_headers.cmake
file(GLOB_RECURSE headers ${PREFIX}/include/hardsphere/*)
if(NOT headers)
  message(FATAL_ERROR "no headers installed under ${PREFIX}/include/hardsphere")
endif()
foreach(h IN LISTS headers)
  file(STRINGS ${h} hits REGEX "immintrin|__AVX|__SSE|__ARM_NEON")
  if(hits)
    message(FATAL_ERROR "${h}: ISA-specific code in an installed header: ${hits}")
  endif()
endforeach()
list(LENGTH headers count)
message(STATUS "${count} installed headers, none ISA-specific")
