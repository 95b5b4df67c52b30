// Which pixels of its tile an image kernel's invocation renders. Workgroup i of the dispatch
// renders the tile's region (i * push.group_stride) mod groups, regions in row order: lavapipe
// hands each of its threads one contiguous run of a dispatch's workgroups, so in plain order
// the thread holding the costlier part of a tile finishes last while the others wait; a
// golden-ratio stride gives every run regions from all over the tile. The stride is coprime
// with the group count, so every region is rendered once, and the image never depends on it.
// CPU twin and the reasons: host/integrator/tiles.rs (`group_stride`, `tile_region`).
#ifndef VKRT_TILE_REGION_GLSL
#define VKRT_TILE_REGION_GLSL

uvec2 tile_slot() {
    uvec2 groups = gl_NumWorkGroups.xy;
    uint count = groups.x * groups.y;
    uint index = gl_WorkGroupID.y * groups.x + gl_WorkGroupID.x;
    // The host gives a stride only for count <= 2^16 (MAX_DEALT_GROUPS), so the product fits.
    uint region = (index * max(push.group_stride, 1u)) % count;
    uvec2 group = uvec2(region % groups.x, region / groups.x);
    // The shape from the host: Mesa 25.0 lavapipe leaves gl_WorkGroupSize at the unspecialised
    // 1 x 1 (it runs the specialised size, but the builtin reads 1).
    return uvec2(push.tile_x, push.tile_y) + group * uvec2(push.group_width, push.group_height) + gl_LocalInvocationID.xy;
}

#endif
