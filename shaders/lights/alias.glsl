// Walker's alias method on the GPU (host/render/alias_table.h builds the tables): O(1) draws
// for light selection and for a mesh light's triangles.
#ifndef PENUMBRA_LIGHTS_ALIAS_GLSL
#define PENUMBRA_LIGHTS_ALIAS_GLSL

#include "shared/types.h"
#include "lights/light_data.glsl"

// Walker's alias method over lightTable/meshTable entries [offset, offset + count) with one
// uniform number: its integer part picks the slot, its fraction flips the slot's coin.
AliasEntry aliasEntry(uint index, bool mesh) {
    // Two separate reads rather than a select of whole structs: the two buffer blocks have
    // distinct struct types in SPIR-V, which such a select violates.
    if (mesh) return loadMeshAlias(index);
    return loadLightAlias(index);
}

AliasEntry sampleAlias(uint offset, uint count, float u, bool mesh) {
    float scaled = u * float(count);
    uint slot = min(uint(scaled), count - 1u);
    float coin = scaled - float(slot);
    AliasEntry e = aliasEntry(offset + slot, mesh);
    if (coin >= e.probability) e = aliasEntry(offset + e.alias, mesh);
    return e;
}

#endif
