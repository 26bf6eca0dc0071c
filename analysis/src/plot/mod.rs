//! Plots of a run-up with plotters, each as PNG and SVG: order plot, cascade,
//! speed plot (order tracks and raw signal over speed) and a displacement overview.
//!
//! Text uses the pure-Rust ab_glyph route with DejaVu Sans compiled in, so no
//! system font lookup happens; [`init_fonts`] registers it (idempotent).
//! Heat maps are rendered as one bitmap of exactly the plot area's pixels (the
//! SVG embeds it as a PNG), so an SVG holds one image instead of ~10^5 rectangles.
//!
//! This file holds what every plot shares: the bundled font and text sizes, the titled white
//! frame, and the output as PNG and SVG (`render_both!`). Each plot kind and each drawing layer
//! that several kinds share has its own file:
//! - `axis.rs`: the amplitude axis (linear, log, dB), the colour map and tick numbers;
//! - `heat.rs`: the heat-map layer (pixels by max hold, overlays, colour bar);
//! - `lines.rs`: the line-plot layer (order tracks, raw-signal bands, legends);
//! - `order.rs`: the order plot and the cascade;
//! - `speed.rs`: the speed plot and the displacement overview;
//! - `pair.rs`: two runs in one picture (`washdyn compare`);
//! - `energy.rs`: the energy balance (`run --energy`).
//!
//! The variant studies' plots (`crate::study::plot`) use the same frame, font and output.

use std::error::Error;
use std::path::Path;
use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};

use super::error::AnalysisError;

/// Render `<base>.png`, and `<base>.svg` where `opts.svg`. Returns the paths.
macro_rules! render_both {
    ($base:expr, $opts:expr, $draw:ident ( $($arg:expr),* )) => {{
        let size = $opts.plot_size;
        let png = $base.with_extension("png");
        let svg = $base.with_extension("svg");
        {
            let mut buf = vec![0u8; size.0 as usize * size.1 as usize * 3];
            {
                let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
                $draw(&root, $($arg),*)
                    .and_then(|_| root.present().map_err(DynErr::from))
                    .map_err(|e| AnalysisError::Plot { path: png.clone(), message: e.to_string() })?;
            }
            write_png(&png, size, &buf)?;
        }
        if $opts.svg {
            {
                let root = SVGBackend::new(&svg, size).into_drawing_area();
                $draw(&root, $($arg),*)
                    .and_then(|_| root.present().map_err(DynErr::from))
                    .map_err(|e| AnalysisError::Plot { path: svg.clone(), message: e.to_string() })?;
            }
            vec![png, svg]
        } else {
            vec![png]
        }
    }};
}
pub(crate) use render_both;

mod axis;
mod energy;
mod heat;
mod lines;
mod order;
mod pair;
mod speed;

pub(crate) use axis::fmt_number;
pub use axis::{AmplitudeAxis, colour_map};
pub use energy::{EnergyLine, energy_plot};
pub(crate) use lines::TRACK_COLOURS;
pub use order::{cascade_plot, order_plot};
pub use pair::{order_plot_pair, track_overlay_plot};
pub use speed::{displacement_plot, speed_plot};

static FONT: &[u8] = include_bytes!("../../../assets/DejaVuSans.ttf");
const FAMILY: &str = "sans-serif";

/// Register the bundled font with plotters once per process. Every plotting entry
/// point calls it; call it yourself before using plotters elsewhere (e.g. benches),
/// because with the `ab_glyph` feature plotters has no other font source.
pub fn init_fonts() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        if register_font(FAMILY, FontStyle::Normal, FONT).is_err() {
            panic!("bundled font assets/DejaVuSans.ttf is not a valid font");
        }
    });
}

pub(crate) type DynErr = Box<dyn Error + Send + Sync>;
pub(crate) type PResult<T = ()> = Result<T, DynErr>;

pub(crate) const TITLE_SIZE: u32 = 28;
pub(crate) const SUBTITLE_SIZE: u32 = 17;
pub(crate) const DESC_SIZE: u32 = 22;
pub(crate) const TICK_SIZE: u32 = 18;
pub(crate) const NOTE_SIZE: u32 = 17;
/// Width reserved right of a heat map for the colour bar, its ticks and caption.
const COLOUR_BAR_AREA: u32 = 200;
/// Colour of plot regions without data (above Nyquist, speed gaps).
const NO_DATA: RGBColor = RGBColor(225, 225, 225);

pub(crate) fn font(size: u32) -> TextStyle<'static> {
    (FAMILY, size).into_font().color(&BLACK)
}

/// A white plot with its title and grey subtitle: the area below them.
pub(crate) fn framed<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    subtitle: &str,
) -> PResult<DrawingArea<DB, Shift>>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    Ok(root
        .titled(title, font(TITLE_SIZE))?
        .titled(subtitle, font(SUBTITLE_SIZE).color(&RGBColor(70, 70, 70)))?)
}

/// Encode an RGB buffer as PNG with the fast deflate level: 2-3x quicker than the default
/// level for plots, for files about a third larger.
pub(crate) fn write_png(path: &Path, size: (u32, u32), rgb: &[u8]) -> Result<(), AnalysisError> {
    let err = |e: String| AnalysisError::Plot {
        path: path.to_path_buf(),
        message: e,
    };
    let file = std::fs::File::create(path).map_err(|e| err(e.to_string()))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), size.0, size.1);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::Fast);
    let mut w = enc.write_header().map_err(|e| err(e.to_string()))?;
    w.write_image_data(rgb).map_err(|e| err(e.to_string()))
}
