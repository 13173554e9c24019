#pragma once
// TRIDENT_FLATTEN marks a traversal whose every call gcc must inline ([[gnu::flatten]]): left to
// its own heuristics, gcc called the triangle test out of line from several walks, a call per
// triangle that cost up to 36% of their time (bench/experiments/packets.md, "Every walk flattened").
//
// Under AddressSanitizer it marks nothing: the instrumented walks, flattened, took gcc more than
// ten minutes a file to compile, and the sanitizer build checks what the code does, not its speed.
#if defined(__SANITIZE_ADDRESS__)
#define TRIDENT_FLATTEN
#else
#define TRIDENT_FLATTEN [[gnu::flatten]]
#endif
