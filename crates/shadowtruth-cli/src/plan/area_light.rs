//! The check, before a plan with PCSS runs, that every light it runs under has an area size.

use super::PlanInputError;
use shadowtruth::scene::Scene;

/// Refuses the first of `lights` (indices into `scene.lights`) that has no area size, at its
/// path in the scene file: PCSS is scored against the area light, which needs the light's size.
pub(super) fn check_area_light_sizes(
    scene: &Scene,
    lights: impl IntoIterator<Item = usize>,
) -> Result<(), PlanInputError> {
    for li in lights {
        if let Err(missing) = scene.lights[li].size() {
            let message = format!(
                "has no {}: pcss is scored against an area light; give the light a size or leave pcss out \
                 of the plan",
                missing.field
            );
            return Err(PlanInputError::one(&scene.source, &format!("lights[{li}]"), message));
        }
    }
    Ok(())
}
