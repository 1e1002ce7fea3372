//! `scnc bench quality`'s log-log plot: relative RMS error against render time, one line for
//! the fixed-count sweep, one for adaptive sampling, the presets as circles. SVG through
//! `plotters` with only its SVG backend and line series (no font rasteriser, no C library:
//! the SVG's text is laid out by the viewer).

use plotters::prelude::*;

use super::Row;

/// The plot of `rows` as an SVG document.
pub fn svg(name: &str, rows: &[Row]) -> Result<String, String> {
    let pts = |kind: &str| -> Vec<(f64, f64)> {
        rows.iter()
            .filter(|r| r.kind == kind && r.seconds > 0.0 && r.error.rel_mse > 0.0)
            .map(|r| (r.seconds, r.error.rel_rms()))
            .collect()
    };
    let all: Vec<(f64, f64)> = ["fixed", "adaptive", "preset"]
        .iter()
        .flat_map(|k| pts(k))
        .collect();
    if all.is_empty() {
        return Err("nothing to plot".into());
    }
    let (t0, t1) = range(all.iter().map(|p| p.0));
    let (e0, e1) = range(all.iter().map(|p| p.1));
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (720, 480)).into_drawing_area();
        root.fill(&WHITE).map_err(msg)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(
                format!("{name}: relative RMS error against time"),
                ("sans-serif", 20),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d((t0..t1).log_scale(), (e0..e1).log_scale())
            .map_err(msg)?;
        chart
            .configure_mesh()
            .x_desc("render time (s)")
            .y_desc("relative RMS error")
            .x_label_formatter(&|v| format!("{v:.3}"))
            .y_label_formatter(&|v| format!("{v:.3}"))
            .draw()
            .map_err(msg)?;
        let series = [
            ("fixed sample counts", pts("fixed"), BLUE),
            ("adaptive (noise target)", pts("adaptive"), RED),
        ];
        for (label, p, colour) in series {
            chart
                .draw_series(LineSeries::new(p, colour.stroke_width(2)))
                .map_err(msg)?
                .label(label)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour));
        }
        let presets = rows.iter().filter(|r| r.kind == "preset");
        chart
            .draw_series(presets.map(|r| {
                EmptyElement::at((r.seconds, r.error.rel_rms()))
                    + Circle::new((0, 0), 5, BLACK.filled())
                    + Text::new(r.label.clone(), (8, -8), ("sans-serif", 14))
            }))
            .map_err(msg)?;
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(msg)?;
        root.present().map_err(msg)?;
    }
    Ok(out)
}

/// A log-scale range around the values, with a margin.
fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    (lo / 1.5, hi * 1.5)
}

fn msg(e: impl std::fmt::Display) -> String {
    format!("cannot draw the plot: {e}")
}
