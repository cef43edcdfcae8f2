// The shadow map's passes: the scene's triangles through the light's clip_from_world (depth
// only; flat triangles as world vertices, placed meshes instanced), and the upload of a given
// layer into a depth texture (frag_depth from an R32Float copy).

struct Light {
    clip_from_world: mat4x4<f32>,
}

@group(0) @binding(0) var<uniform> light: Light;

@vertex
fn caster(@location(0) world: vec3<f32>) -> @builtin(position) vec4<f32> {
    // Column by column, in the order of the CPU's f32 product (src/raster/rasterize.rs), so that
    // both start from the same clip coordinates.
    let m = light.clip_from_world;
    return m[0] * world.x + m[1] * world.y + m[2] * world.z + m[3];
}

// A placed mesh's vertex: its placement's three affine rows (world = row · (p, 1)) in f32, as
// an engine's instanced draw, then the light's matrix as `caster`.
@vertex
fn caster_instanced(
    @location(0) local: vec3<f32>,
    @location(1) row_x: vec4<f32>,
    @location(2) row_y: vec4<f32>,
    @location(3) row_z: vec4<f32>,
) -> @builtin(position) vec4<f32> {
    let p = vec4<f32>(local, 1.0);
    let world = vec3<f32>(dot(row_x, p), dot(row_y, p), dot(row_z, p));
    let m = light.clip_from_world;
    return m[0] * world.x + m[1] * world.y + m[2] * world.z + m[3];
}

@group(0) @binding(1) var layer: texture_2d<f32>;

@vertex
fn fullscreen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let x = f32((i << 1u) & 2u) * 2.0 - 1.0;
    let y = f32(i & 2u) * 2.0 - 1.0;
    return vec4<f32>(x, y, 0.0, 1.0);
}

@fragment
fn upload(@builtin(position) pixel: vec4<f32>) -> @builtin(frag_depth) f32 {
    return textureLoad(layer, vec2<i32>(pixel.xy), 0).r;
}
