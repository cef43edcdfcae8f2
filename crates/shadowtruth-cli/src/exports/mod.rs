//! The single-file writers: report.csv, the gate's JUnit XML, soft reference EXRs, depth maps,
//! world-space OBJ and mask PNGs. Each writes one file (atomically) from what it is given.

pub mod csv_rows;
mod depth_map;
mod junit;
mod mask_png;
mod obj;
mod soft_exr;

pub use depth_map::write_depth_map;
pub use junit::junit_xml;
pub use mask_png::write_mask_png;
pub use obj::write_world_obj;
pub use soft_exr::write_soft_exr;
