// Walker's alias method on the GPU (host/render/alias_table.h builds the tables): O(1) draws
// for light selection and for a mesh light's triangles.
#ifndef PENUMBRA_LIGHTS_ALIAS_GLSL
#define PENUMBRA_LIGHTS_ALIAS_GLSL

#include "shared/types.h"
#include "lights/light_data.glsl"
#include "common/rng.glsl"
#include "sampling/warp.glsl"

// Walker's alias method over lightTable/meshTable entries [offset, offset + count) with one
// uniform number: its integer part picks the slot, its fraction flips the slot's coin.
AliasEntry aliasEntry(uint index, bool mesh) {
    // Two separate reads rather than a select of whole structs: the two buffer blocks have
    // distinct struct types in SPIR-V, which such a select violates.
    if (mesh) return loadMeshAlias(index);
    return loadLightAlias(index);
}

// The draw from a 32-bit fraction, which also returns what is left of it: uniform on [0,1)
// given the entry drawn (sampling/warp.glsl, remapAfterChoice), for the sample that
// follows (lights.glsl, selectLight). The slot is the integer part of bits * count in 64
// bits, so the coin keeps min(24, 32 - log2(count)) random bits, where a float u * count
// would keep 24 - log2(count).
AliasEntry sampleAlias(uint offset, uint count, uint bits, bool mesh, out float rest) {
    uint slot, fraction;
    umulExtended(bits, count, slot, fraction);
    float coin = bitsToUnit(fraction);
    AliasEntry e = aliasEntry(offset + slot, mesh);
    rest = remapAfterChoice(coin, e.probability);
    if (coin >= e.probability) e = aliasEntry(offset + e.alias, mesh);
    return e;
}

// The same draw from a uniform float in [0,1) (a mesh light's triangle): its 24 bits are the
// fraction's top bits, exactly.
AliasEntry sampleAlias(uint offset, uint count, float u, bool mesh) {
    float unused;
    return sampleAlias(offset, count, uint(u * 4294967296.0), mesh, unused);
}

#endif
