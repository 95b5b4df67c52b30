// Mirror of host/gpu_abi/ (nodes.rs, scene_data.rs, dispatch.rs): same structs, same field names,
// same order. tests/layout.rs checks every offset, size and stride here against the Rust side
// (gpu_abi::ALL_STRUCTS).
#ifndef VKRT_LAYOUT_GLSL
#define VKRT_LAYOUT_GLSL

struct GpuNode {
    vec3 bmin;
    uint escape;
    vec3 bmax;
    uint leaf;
};

struct GpuParentNode {
    vec3 bmin;
    uint parent;
    vec3 bmax;
    uint leaf;
};

struct GpuCompactNode {
    uint min_xy;
    uint min_z_max_x;
    uint max_yz;
    uint link;
};

struct GpuWideNode {
    vec4 min_x;
    vec4 min_y;
    vec4 min_z;
    vec4 max_x;
    vec4 max_y;
    vec4 max_z;
    uvec4 children;
    uint parent;
    uint info;
    uint _pad0;
    uint _pad1;
};

struct GpuTriangle {
    vec3 v0;
    uint prim;
    vec3 v1;
    uint shading;
    vec3 v2;
    uint _pad1;
};

struct GpuInstance {
    vec4 world_to_object[3];
    vec4 object_to_world[3];
    uint root;
    uint prim_base;
    uint flags;
    uint shading_base;
    vec3 grid_origin;
    uint order_nodes;
    vec3 grid_scale;
    uint node_end;
};

struct GpuShading {
    vec3 n0;
    uint material;
    vec3 n1;
    uint _pad0;
    vec3 n2;
    uint _pad1;
};

struct GpuMaterial {
    vec3 diffuse;
    uint flags;
    vec3 specular;
    float shininess;
    vec3 emission;
    float ior;
    uint diffuse_texture;
    uint alpha_texture;
    uint emission_texture;
    float alpha_cutoff;
    float metallic;
    float roughness;
    uint metallic_roughness_texture;
    float normal_scale;
    uint normal_texture;
    uint _pad0;
    uint _pad1;
    uint _pad2;
};

struct GpuTangents {
    vec4 t0;
    vec4 t1;
    vec4 t2;
};

struct GpuTexture {
    uint offset;
    uint width;
    uint height;
    uint _pad0;
};

struct GpuUv {
    vec2 uv0;
    vec2 uv1;
    vec2 uv2;
    uint _pad0;
    uint _pad1;
};

struct GpuLight {
    vec3 position;
    uint kind;
    vec3 direction;
    float radius;
    vec3 intensity;
    float cos_outer;
};

struct GpuEmitter {
    vec3 v0;
    uint prim;
    vec3 v1;
    float area;
    vec3 v2;
    uint flags;
    vec3 radiance;
    uint _pad1;
};

struct GpuFrame {
    vec3 cam_origin;
    float tan_half_fov_y;
    vec3 cam_forward;
    float aspect;
    vec3 cam_right;
    uint width;
    vec3 cam_up;
    uint height;
    vec3 ambient;
    uint max_depth;
    uint light_count;
    uint emitter_count;
    uint seed;
    float scene_scale;
    vec3 sky_color;
    uint sky_texture;
    float aperture_radius;
    float focus_distance;
    uint env_width;
    uint env_height;
    float env_rotation_cos;
    float env_rotation_sin;
    float env_pick_pmf;
    float env_compensation;
};

struct GpuPush {
    uint tile_x;
    uint tile_y;
    uint sample_base;
    uint sample_count;
    uint total_spp;
    uint ray_count;
    uint any_hit;
    uint node_count;
    vec3 grid_origin;
    uint group_stride;
    vec3 grid_scale;
    uint group_width;
    uint group_height;
    uint probe;
    uint list_first;
    uint list_count;
    uint top_order_nodes;
    uint top_nodes;
    uint _pad1;
    uint _pad2;
};

struct GpuRay {
    vec3 origin;
    float tmin;
    vec3 direction;
    float tmax;
};

struct GpuHit {
    float t;
    uint prim;
    float u;
    float v;
    uint nodes_visited;
    uint tris_tested;
    uint _pad0;
    uint _pad1;
};

struct GpuMirror {
    vec3 v0;
    uint material;
    vec3 v1;
    uint _pad0;
    vec3 v2;
    uint _pad1;
};

struct GpuCaster {
    vec3 center;
    float radius;
    vec3 target;
    float target_radius;
    float spot_spread;
    uint _pad0;
    uint _pad1;
    uint _pad2;
};

struct GpuMirrorPlane {
    uint first;
    uint count;
    uint _pad0;
    uint _pad1;
};

struct GpuLightPick {
    float pmf;
    uint alias;
    float threshold;
    float alias_pmf;
};

struct GpuPathParams {
    uint max_depth;
    uint rr_depth;
    uint sampler_kind;
    uint sample_rate;
    uint pick_count;
    uint nee;
    float inv_total_weight;
    uint coherence;
    uint adaptive;
    uint coherence_block_bits;
    uint zsobol_log2;
    uint mirror_count;
    uint caster_count;
    uint _pad0;
    uint _pad1;
    uint _pad2;
};

#endif
