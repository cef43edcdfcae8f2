//! What is drawn from a report: the figures of each run and view (PNG, through the indexed
//! image), the plots (SVG and PNG, plotters), the animated error maps and flicker maps of runs
//! over a path, the summaries and the HTML page (`index.html`, with `page.js`).

mod answer_section;
mod bundled_font;
mod cascades_section;
pub mod figures;
pub mod flicker_map;
pub mod frame_movie;
pub mod frame_plots;
pub mod html;
pub mod indexed_image;
pub mod palette;
pub mod pareto;
mod path_section;
pub mod plots;
mod point_map_section;
pub mod summary;
mod summary_table;
pub mod text;
mod tune_plot;

pub use html::write_page;
pub use plots::write_chart;
pub use tune_plot::tune_chart;
