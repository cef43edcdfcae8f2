// The shadow test of every camera pixel, on the reference G-buffer's surface points: the same
// formulas, in the same f32 order, as the CPU techniques (src/technique/bias.rs,
// normal_offset.rs, pcf.rs, kernel.rs).

struct Params {
    clip_from_world: mat4x4<f32>,
    // Row z of light_from_world: view depth D = −(row · (p, 1)).
    view_z_row: vec4<f32>,
    // xyz toward the light; w = 1 for a directional light.
    to_light: vec4<f32>,
    // xyz the light's position; w = 1 for a spot light.
    light_position: vec4<f32>,
    width: u32,
    height: u32,
    resolution: u32,
    technique: u32,
    bias_depth: f32,
    bias_world: f32,
    scale_texels: f32,
    one_minus_n_dot_l: u32,
    kernel_size: u32,
    perspective: u32,
    ortho_texel_world: f32,
    tan_half_fov: f32,
    near: f32,
    far: f32,
    pad0: u32,
    pad1: u32,
}

// Technique ids (GpuTechnique in src/gpu/technique.rs).
const PLAIN: u32 = 0u;
const CONSTANT_DEPTH: u32 = 1u;
const CONSTANT_WORLD: u32 = 2u;
const NORMAL_OFFSET: u32 = 3u;
const PCF_BOX: u32 = 4u;
const PCF_BILINEAR: u32 = 5u;

@group(0) @binding(0) var<uniform> params: Params;
// Per camera pixel: xyz the surface point, w = 1 where the pixel is evaluated.
@group(0) @binding(1) var<storage, read> positions: array<vec4<f32>>;
// Per camera pixel: the unit geometric normal.
@group(0) @binding(2) var<storage, read> normals: array<vec4<f32>>;
@group(0) @binding(3) var shadow_map: texture_depth_2d;
@group(0) @binding(4) var compare_sampler: sampler_comparison;

@vertex
fn fullscreen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let x = f32((i << 1u) & 2u) * 2.0 - 1.0;
    let y = f32(i & 2u) * 2.0 - 1.0;
    return vec4<f32>(x, y, 0.0, 1.0);
}

// (u, v, d) of p, or w ≤ 0 in the last component's place (LightView::project).
fn project(p: vec3<f32>) -> vec4<f32> {
    let m = params.clip_from_world;
    let c = m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3];
    if (c.w <= 0.0) {
        return vec4<f32>(0.0, 0.0, 0.0, 0.0);
    }
    let inv_w = 1.0 / c.w;
    return vec4<f32>(0.5 * c.x * inv_w + 0.5, 0.5 * c.y * inv_w + 0.5, c.z * inv_w, 1.0);
}

fn view_depth(p: vec3<f32>) -> f32 {
    let r = params.view_z_row;
    return -(r.x * p.x + r.y * p.y + r.z * p.z + r.w);
}

fn depth_of_view_depth(d: f32) -> f32 {
    let n = params.near;
    let f = params.far;
    if (params.perspective == 1u) {
        return f * (d - n) / (d * (f - n));
    }
    return (d - n) / (f - n);
}

fn texel_world_size(p: vec3<f32>) -> f32 {
    if (params.perspective == 1u) {
        return 2.0 * view_depth(p) * params.tan_half_fov / f32(params.resolution);
    }
    return params.ortho_texel_world;
}

fn map_depth(x: i32, row: i32) -> f32 {
    let last = i32(params.resolution) - 1;
    return textureLoad(shadow_map, vec2<i32>(clamp(x, 0, last), clamp(row, 0, last)), 0);
}

// The classic test at the texel holding (u, v), clamped to the map (technique::depth_test).
fn depth_test(uvd: vec3<f32>, bias: f32) -> f32 {
    let n = f32(params.resolution);
    let last = params.resolution - 1u;
    let x = min(u32(max(uvd.x * n, 0.0)), last);
    let row = min(u32(max((1.0 - uvd.y) * n, 0.0)), last);
    return select(0.0, 1.0, uvd.z - bias <= map_depth(i32(x), i32(row)));
}

// k×k point taps one texel apart around the receiver, equal weights (kernel.rs, Box).
fn box_filter(uvd: vec3<f32>, bias: f32) -> f32 {
    let n = f32(params.resolution);
    let xs = uvd.x * n;
    let ys = (1.0 - uvd.y) * n;
    let k = params.kernel_size;
    let w = 1.0 / f32(k * k);
    let half = (f32(k) - 1.0) * 0.5;
    let d = uvd.z - bias;
    var visibility = 0.0;
    for (var b = 0u; b < k; b++) {
        for (var a = 0u; a < k; a++) {
            let x = i32(floor(xs + f32(a) - half));
            let row = i32(floor(ys + f32(b) - half));
            visibility += w * select(0.0, 1.0, d <= map_depth(x, row));
        }
    }
    return clamp(visibility, 0.0, 1.0);
}

fn visibility(p: vec3<f32>, normal: vec3<f32>) -> f32 {
    var q = p;
    if (params.technique == NORMAL_OFFSET) {
        var l = params.to_light.xyz;
        if (params.to_light.w != 1.0) {
            if (params.light_position.w != 1.0) {
                return 1.0;
            }
            let to = params.light_position.xyz - p;
            l = to * (1.0 / sqrt(dot(to, to)));
        }
        let n_dot_l = clamp(dot(normal, l), 0.0, 1.0);
        var g = sqrt(max(1.0 - n_dot_l * n_dot_l, 0.0));
        if (params.one_minus_n_dot_l == 1u) {
            g = 1.0 - n_dot_l;
        }
        q = p + normal * (params.scale_texels * texel_world_size(p) * g);
    }
    let projected = project(q);
    if (projected.w == 0.0) {
        return 1.0;
    }
    let uvd = projected.xyz;
    switch params.technique {
        case CONSTANT_DEPTH: {
            return depth_test(uvd, params.bias_depth);
        }
        case CONSTANT_WORLD: {
            let d_view = view_depth(p);
            return depth_test(uvd, depth_of_view_depth(d_view) - depth_of_view_depth(d_view - params.bias_world));
        }
        case PCF_BOX: {
            return box_filter(uvd, params.bias_depth);
        }
        case PCF_BILINEAR: {
            // The hardware's compare-then-filter over the 2×2 texels around (u, v): the
            // comparison is `reference ≤ texel`, as the CPU's `d ≤ z`.
            let r = uvd.z - params.bias_depth;
            return textureSampleCompareLevel(shadow_map, compare_sampler, vec2<f32>(uvd.x, 1.0 - uvd.y), r);
        }
        default: {
            return depth_test(uvd, 0.0);
        }
    }
}

@fragment
fn shade(@builtin(position) pixel: vec4<f32>) -> @location(0) vec4<f32> {
    let i = u32(pixel.y) * params.width + u32(pixel.x);
    let p = positions[i];
    if (p.w != 1.0) {
        return vec4<f32>(1.0, 0.0, 0.0, 0.0);
    }
    return vec4<f32>(visibility(p.xyz, normals[i].xyz), 0.0, 0.0, 0.0);
}
