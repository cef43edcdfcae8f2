//! Figure 12 of Ehm et al. (WSCG 2015) as the paper lays it out: per setting the front error map,
//! the featured trunk enlarged and the back error map, (a)–(i) in the paper's order, then the
//! ray-traced references of both sides, (j) and (k).

use super::measure::{Rect, View};
use crate::drawing::figures::{
    GridCell, ViewCanvas, grid, reference_visibility, run_images, visibility_image, zoom,
};
use std::path::Path;

const SETTING_NAMES: [&str; 3] = ["original K=0.0001", "original K=0.01", "enhanced K=0.0001"];
const LETTERS: [[&str; 3]; 3] = [["(a)", "(b)", "(c)"], ["(d)", "(e)", "(f)"], ["(g)", "(h)", "(i)"]];
/// Enlargement of the trunk's box.
const TRUNK_ZOOM: u32 = 4;
/// Widest cell of the grid, in pixels.
const CELL_WIDTH: u32 = 512;

/// Writes the grid into `dir/file`; `visibilities` holds (front, back) per setting, in the order
/// of `SETTING_NAMES`.
pub(super) fn write_figure12(
    dir: &Path,
    file: &str,
    front: &View,
    back: &View,
    visibilities: &[(Vec<f32>, Vec<f32>)],
    trunk_box: Rect,
) -> std::io::Result<()> {
    let canvas = |v: &View| ViewCanvas::new(&v.gbuffer, &v.reference, &v.light);
    let (front_canvas, back_canvas) = (canvas(front), canvas(back));
    let mut images = Vec::new();
    for ((name, (v_front, v_back)), l) in SETTING_NAMES.iter().zip(visibilities).zip(LETTERS) {
        let (_, e_front) = run_images(&front.gbuffer, &front.reference, v_front, &front_canvas);
        let (_, e_back) = run_images(&back.gbuffer, &back.reference, v_back, &back_canvas);
        let trunk = zoom(&e_front, trunk_box, TRUNK_ZOOM);
        images.push((format!("{} {name}, front", l[0]), e_front));
        images.push((format!("{} {name}, trunk enlarged", l[1]), trunk));
        images.push((format!("{} {name}, back", l[2]), e_back));
    }
    let reference = |v: &View, c: &ViewCanvas| {
        visibility_image(&v.gbuffer, c, &reference_visibility(&v.gbuffer, &v.reference))
    };
    images.push(("(j) ray-traced reference, front".into(), reference(front, &front_canvas)));
    images.push(("(k) ray-traced reference, back".into(), reference(back, &back_canvas)));
    let cells: Vec<GridCell> =
        images.iter().map(|(caption, image)| GridCell { image, caption: caption.clone() }).collect();
    grid(&cells, 3, CELL_WIDTH).write_png(&dir.join(file))
}
