/* sdf_morton.h: the 63-bit Morton key of a brick, shared by every kernel that orders or finds leaf
 * bricks (kernel side only). Bit j of x is key bit 3j, of y 3j+1, of z 3j+2 (21 bits per axis), as
 * sdf_morton_child numbers the children inside a parent; a brick of a coarser level than the finest
 * (adaptive builds) is keyed by its low corner on the finest lattice. */
#ifndef SDFBRICK_SDF_MORTON_H
#define SDFBRICK_SDF_MORTON_H

#include "sdf_types.h"

/* Spreads the low 21 bits of v two bits apart (bit i -> bit 3i). */
inline ulong sdf_spread21(uint v) {
    ulong x = (ulong)(v & 0x1FFFFFu);
    x = (x | (x << 32)) & 0x1F00000000FFFFUL;
    x = (x | (x << 16)) & 0x1F0000FF0000FFUL;
    x = (x | (x << 8)) & 0x100F00F00F00F00FUL;
    x = (x | (x << 4)) & 0x10C30C30C30C30C3UL;
    x = (x | (x << 2)) & 0x1249249249249249UL;
    return x;
}

/* Key of lattice coordinate c of a level whose cells are 2^shift finest cells wide. */
inline ulong sdf_lattice_key(int3 c, uint shift) {
    return sdf_spread21((uint)c.x << shift) | (sdf_spread21((uint)c.y << shift) << 1) |
           (sdf_spread21((uint)c.z << shift) << 2);
}

inline ulong sdf_brick_key(SdfBrick b, uint finest, uint log2b) {
    return sdf_lattice_key((int3)(b.coord[0], b.coord[1], b.coord[2]), (finest - b.level) * log2b);
}

#endif /* SDFBRICK_SDF_MORTON_H */
