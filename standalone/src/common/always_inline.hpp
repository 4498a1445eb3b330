#pragma once
//! HS_ALWAYS_INLINE: inline even where the compiler's heuristics would not.
//!
//! Two uses. Hot helpers called per neighbour (the resolver's consider()). And every helper
//! whose body only requests cache lines: GCC treats __builtin_prefetch as free of side
//! effects, so its inter-procedural analysis finds such a function "const" and deletes the
//! calls (GCC 12 at -O2 and above). Inlined first, the prefetches survive.
#if defined(__GNUC__)
#define HS_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define HS_ALWAYS_INLINE inline
#endif
