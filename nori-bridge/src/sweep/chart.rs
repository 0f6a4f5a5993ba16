//! One kind of chart, drawn with plotters into a PNG: labelled points in
//! coloured series against a logarithmic y axis whose floor band stands
//! for zero (a log axis has no 0), optionally with a Pareto front.

use anyhow::{anyhow, bail, Context, Result};
use plotters::prelude::*;
use std::path::Path;
use std::sync::OnceLock;

/// DejaVu Sans from Debian's fonts-dejavu-core, loaded at run time
/// (plotters' ab_glyph backend has no system font lookup).
pub const FONT_FILE: &str = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
pub const FONT: &str = "sans-serif";
const SIZE: (u32, u32) = (1100, 750);

/// Registers DejaVu Sans under the name FONT once per process.
pub fn register_font() -> Result<()> {
    static DONE: OnceLock<Result<(), String>> = OnceLock::new();
    DONE.get_or_init(|| {
        let bytes = std::fs::read(FONT_FILE).map_err(|e| {
            format!("{FONT_FILE}: {e} (install the Debian package fonts-dejavu-core)")
        })?;
        let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
        plotters::style::register_font(FONT, FontStyle::Normal, bytes)
            .map_err(|_| format!("{FONT_FILE}: not a usable TrueType font"))
    })
    .clone()
    .map_err(|e| anyhow!(e))
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Marker {
    Circle,
    Triangle,
}

pub struct Point {
    pub x: f64,
    /// 0 is drawn in the floor band.
    pub y: f64,
    pub label: String,
}

pub struct Series {
    pub name: String,
    pub color: RGBColor,
    pub marker: Marker,
    /// Join the points (in the given order) with a line.
    pub joined: bool,
    pub points: Vec<Point>,
}

pub struct Chart {
    pub title: String,
    pub x_desc: String,
    pub y_desc: String,
    /// Label x ticks as integers (LUTs, bits).
    pub x_integer: bool,
    pub series: Vec<Series>,
    /// Pareto front points, joined left to right and ringed.
    pub front: Vec<(f64, f64)>,
}

/// The log y range: a decade below the smallest non-zero value to above
/// the largest; the floor band [lo, lo * 3) holds the zeros at lo * 1.7.
fn y_range(ys: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    let nz = ys.filter(|y| *y > 0.0);
    let min = nz.clone().fold(f64::INFINITY, f64::min);
    let max = nz.fold(0.0, f64::max);
    if max == 0.0 {
        return (0.1, 100.0);
    }
    let lo = 10f64.powf(min.log10().floor() - 1.0);
    let hi = 10f64.powf(max.log10().floor() + 1.0).max(lo * 100.0);
    (lo, hi)
}

fn x_range(xs: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    let pad = ((hi - lo) * 0.08).max(hi.abs() * 0.05).max(1e-9);
    (lo - pad, hi + pad)
}

pub fn draw(chart: &Chart, path: &Path) -> Result<()> {
    register_font()?;
    let all = || chart.series.iter().flat_map(|s| s.points.iter());
    if all().next().is_none() {
        bail!("{}: nothing to plot", path.display());
    }
    if let Some(p) = all().find(|p| !(p.x.is_finite() && p.y >= 0.0 && p.y.is_finite())) {
        bail!(
            "{}: point '{}' has x {} and y {}, not plottable",
            path.display(),
            p.label,
            p.x,
            p.y
        );
    }
    let mut buf = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    render(chart, &mut buf).map_err(|e| anyhow!("{}: drawing failed: {e}", path.display()))?;
    let img = image::RgbImage::from_raw(SIZE.0, SIZE.1, buf).context("image buffer size")?;
    img.save(path)
        .with_context(|| format!("{}: cannot write", path.display()))
}

fn render(c: &Chart, buf: &mut [u8]) -> Result<(), Box<dyn std::error::Error>> {
    let pts = || c.series.iter().flat_map(|s| s.points.iter());
    let (x0, x1) = x_range(pts().map(|p| p.x));
    let (lo, hi) = y_range(pts().map(|p| p.y));
    let band_top = lo * 3.0;
    let at = |y: f64| if y > 0.0 { y } else { lo * 1.7 };
    let root = BitMapBackend::with_buffer(buf, SIZE).into_drawing_area();
    root.fill(&WHITE)?;
    let mut ch = ChartBuilder::on(&root)
        .caption(&c.title, (FONT, 24))
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(x0..x1, (lo..hi).log_scale())?;
    let y_fmt = |v: &f64| {
        if *v < band_top {
            String::new()
        } else {
            format!("{v:.0e}")
        }
    };
    let x_fmt = |v: &f64| {
        if c.x_integer {
            format!("{v:.0}")
        } else {
            format!("{v:.3}")
        }
    };
    ch.configure_mesh()
        .x_desc(&c.x_desc)
        .x_label_formatter(&x_fmt)
        .y_desc(&c.y_desc)
        .y_label_formatter(&y_fmt)
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 17))
        .draw()?;
    ch.draw_series(std::iter::once(Rectangle::new(
        [(x0, lo), (x1, band_top)],
        RGBColor(225, 225, 225).filled(),
    )))?;
    ch.draw_series(std::iter::once(Text::new(
        "0 (none)",
        (x0, lo * 2.5),
        (FONT, 15),
    )))?;
    if !c.front.is_empty() {
        let mut line: Vec<(f64, f64)> = c.front.iter().map(|&(x, y)| (x, at(y))).collect();
        line.sort_by(|a, b| a.0.total_cmp(&b.0));
        ch.draw_series(LineSeries::new(line.clone(), BLACK.stroke_width(2)))?
            .label("Pareto front")
            .legend(|(x, y)| PathElement::new([(x - 8, y), (x + 8, y)], BLACK.stroke_width(2)));
        ch.draw_series(
            line.into_iter()
                .map(|q| Circle::new(q, 10, BLACK.stroke_width(2))),
        )?;
    }
    // Labels of the series alternate above and below their points, so the
    // variants of one format (close in x) do not print over each other.
    const LABEL_DY: [i32; 4] = [-20, 8, -32, 20];
    for (k, s) in c.series.iter().enumerate() {
        let color = s.color;
        let dy = LABEL_DY[k % LABEL_DY.len()];
        if s.joined {
            ch.draw_series(LineSeries::new(
                s.points.iter().map(|p| (p.x, at(p.y))),
                color.stroke_width(1),
            ))?;
        }
        let xy = || s.points.iter().map(|p| (p.x, at(p.y)));
        match s.marker {
            Marker::Circle => ch
                .draw_series(xy().map(|q| Circle::new(q, 6, color.filled())))?
                .legend(move |(x, y)| Circle::new((x, y), 6, color.filled())),
            Marker::Triangle => ch
                .draw_series(xy().map(|q| TriangleMarker::new(q, 7, color.filled())))?
                .legend(move |(x, y)| TriangleMarker::new((x, y), 7, color.filled())),
        }
        .label(&s.name);
        ch.draw_series(s.points.iter().map(|p| {
            EmptyElement::at((p.x, at(p.y)))
                + Text::new(
                    p.label.clone(),
                    (8, dy),
                    (FONT, 13).into_font().color(&color),
                )
        }))?;
    }
    // Middle right: the sweep's plots fall from upper left to lower right, leaving it empty.
    ch.configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((FONT, 15))
        .position(SeriesLabelPosition::MiddleRight)
        .draw()?;
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn y_range_spans_a_decade_below_the_least_non_zero_value() {
        let (lo, hi) = y_range([0.0, 3.0, 250.0].into_iter());
        assert_eq!((lo, hi), (0.1, 1000.0));
        assert_eq!(y_range([0.0, 0.0].into_iter()), (0.1, 100.0));
    }
}
