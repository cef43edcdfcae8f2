// The shadow-only pass: Bevy's own shadow lookup for the view's one light, written raw.
// R = the shadow factor (1 lit, 0 shadowed), G + B = the distance from the camera to the surface
// split into an f16-exact high part and the remainder (the camera's HDR target is Rgba16Float,
// bevy_render's ViewTarget::TEXTURE_FORMAT_HDR), A = 1; the target is cleared to alpha 0.

#import bevy_pbr::{
    forward_io::VertexOutput,
    mesh_view_bindings as view_bindings,
    shadows,
}

@fragment
fn fragment(@builtin(front_facing) is_front: bool, in: VertexOutput) -> @location(0) vec4<f32> {
    // As bevy_pbr's pbr_functions::prepare_world_normal: the back face of a double-sided
    // material looks up its shadow with the normal turned towards the camera.
#ifdef SHADOW_ONLY_DOUBLE_SIDED
    let normal = select(-in.world_normal, in.world_normal, is_front);
#else
    let normal = in.world_normal;
#endif

#ifdef SHADOW_ONLY_SPOT
    // The one clusterable object is the spot light (bevy_pbr's render/light.rs sorts point
    // lights before spot lights; there are no point lights).
    let shadow = shadows::fetch_spot_shadow(
        0u,
        in.world_position,
        normal,
        view_bindings::clusterable_objects.data[0].shadow_map_near_z,
    );
#else
    // As bevy_pbr's pbr_functions::apply_pbr_lighting (0.16).
    let view_z = dot(vec4<f32>(
        view_bindings::view.view_from_world[0].z,
        view_bindings::view.view_from_world[1].z,
        view_bindings::view.view_from_world[2].z,
        view_bindings::view.view_from_world[3].z
    ), in.world_position);
    let shadow = shadows::fetch_directional_shadow(0u, in.world_position, normal, view_z);
#endif

    let distance_world = distance(in.world_position.xyz, view_bindings::view.world_position);
    let high = unpack2x16float(pack2x16float(vec2<f32>(distance_world, 0.0))).x;
    return vec4<f32>(shadow, high, distance_world - high, 1.0);
}
