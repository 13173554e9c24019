#pragma once
// prefetch_line(p): asks for the cache line holding p to be brought into every cache level, and
// is never dropped by the compiler.
//
// Why not __builtin_prefetch: gcc 12's mod/ref analysis counts a prefetch as having no effect, so
// a lambda or inline function whose only work is prefetching is judged side-effect free and every
// call to it is deleted, loop and all. The Python module's prefetch of the next tile's rays
// compiled to no instruction at all (objdump), and so did a first form of the wide BVH collapse's
// prefetch of the triangles ahead. An asm statement marked volatile is kept where it stands; it
// only reads the byte it names and writes nothing, so the code around it is scheduled as before.
namespace trident {

inline void prefetch_line(const void* p) { asm volatile("prefetcht0 %0" : : "m"(*static_cast<const char*>(p))); }

}  // namespace trident
