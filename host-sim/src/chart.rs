//! One chart helper for every plot the tools draw (SVG text through `plotters`): line charts,
//! side-by-side scatter panels and grouped bars, with one palette and one frame style.

use crate::error::{chart as err, Result};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Measured signals.
pub const MEASURED: RGBColor = RGBColor(40, 40, 40);
/// The reference a result is compared with: the first model, the plain controller.
pub const FIRST_MODEL: RGBColor = RGBColor(214, 96, 77);
/// The result: the final model, the full controller.
pub const FINAL_MODEL: RGBColor = RGBColor(33, 102, 172);
/// An alternative the result is checked against: the Maxwell-slip contact in the final model's
/// bristle's place.
pub const ALTERNATIVE: RGBColor = RGBColor(230, 159, 0);
/// Positive direction of motion.
pub const PLUS: RGBColor = RGBColor(27, 120, 55);
/// Negative direction of motion.
pub const MINUS: RGBColor = RGBColor(153, 112, 171);
/// Width of every chart \[px\].
pub const WIDTH: u32 = 900;

/// A chart's frame: title, axis descriptions with units, and ranges.
#[derive(Clone, Debug)]
pub struct Frame<'a> {
    /// Caption.
    pub title: &'a str,
    /// x axis description with unit.
    pub x_desc: &'a str,
    /// y axis description with unit.
    pub y_desc: &'a str,
    /// x range.
    pub x: (f64, f64),
    /// y range.
    pub y: (f64, f64),
}

/// One labelled line.
#[derive(Clone, Debug)]
pub struct Line<'a> {
    /// Legend label.
    pub label: &'a str,
    /// Colour.
    pub color: RGBColor,
    /// Points (x, y).
    pub points: Vec<(f64, f64)>,
}

/// One scatter panel: a frame and coloured points.
#[derive(Clone, Debug)]
pub struct Panel<'a> {
    /// The frame.
    pub frame: Frame<'a>,
    /// Points (x, y, colour).
    pub points: Vec<(f64, f64, RGBColor)>,
    /// Radius of the points \[px\] (1 for thousands of samples, more for a few events).
    pub radius: u32,
    /// Points drawn as rings over the filled ones, a little larger (x, y, colour): what a model
    /// is compared with, so a model point on it stays visible inside the ring.
    pub rings: Vec<(f64, f64, RGBColor)>,
}

/// One series of bars.
#[derive(Clone, Debug)]
pub struct Bars<'a> {
    /// Legend label.
    pub label: &'a str,
    /// Colour.
    pub color: RGBColor,
    /// One value per category.
    pub values: Vec<f64>,
}

/// Height of one legend entry as plotters draws it \[px\], generous.
const LEGEND_ROW_PX: f64 = 20.0;
/// Width of a legend label's character (the default 15 px font) \[px\], generous.
const LEGEND_PX_PER_CHAR: f64 = 8.0;

/// A stretch of the plotting area the data occupy, `(x_min, x_max, y_min, y_max)` in data
/// coordinates: a line's segment, a bar, a reference line.
type Occupied = (f64, f64, f64, f64);

/// The bounding box of each segment of a line: a steep jump through a corner occupies it even
/// where no sample falls inside.
fn segments(points: &[(f64, f64)]) -> impl Iterator<Item = Occupied> + Clone + '_ {
    points.windows(2).map(|w| {
        (
            w[0].0.min(w[1].0),
            w[0].0.max(w[1].0),
            w[0].1.min(w[1].1),
            w[0].1.max(w[1].1),
        )
    })
}

/// The corner of the plotting area where a legend of `labels` overlaps the fewest `occupied`
/// stretches, so that it hides no data where a corner is free (plotters' default, the middle of
/// the right edge, sat on the force trace). `area_px` is the plotting area's size in pixels;
/// ties go to the upper right, then the upper left, the lower right, the lower left.
fn quiet_corner(
    frame: ((f64, f64), (f64, f64)),
    area_px: (u32, u32),
    labels: &[&str],
    occupied: impl Iterator<Item = Occupied> + Clone,
) -> SeriesLabelPosition {
    let (x, y) = frame;
    let longest = labels.iter().map(|l| l.chars().count()).max().unwrap_or(0) as f64;
    // the box with its marker, padding and plotters' margin from the frame, as a share of the
    // plotting area's span in data units
    let wx = ((50.0 + LEGEND_PX_PER_CHAR * longest) / f64::from(area_px.0.max(1))).min(1.0)
        * (x.1 - x.0);
    let wy = ((20.0 + LEGEND_ROW_PX * labels.len() as f64) / f64::from(area_px.1.max(1))).min(1.0)
        * (y.1 - y.0);
    // the span `w` wide at the high or the low end of `(lo, hi)`
    let end =
        |(lo, hi): (f64, f64), w: f64, high: bool| if high { (hi - w, hi) } else { (lo, lo + w) };
    let covered = |right: bool, upper: bool| {
        let ((bx0, bx1), (by0, by1)) = (end(x, wx, right), end(y, wy, upper));
        occupied
            .clone()
            .filter(|&(x0, x1, y0, y1)| x0 <= bx1 && x1 >= bx0 && y0 <= by1 && y1 >= by0)
            .count()
    };
    // (min_by_key keeps the first of equals: the order is the preference)
    [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ]
    .into_iter()
    .min_by_key(|(_, right, upper)| covered(*right, *upper))
    .map_or(SeriesLabelPosition::UpperRight, |c| c.0)
}

/// A line chart `height` px high.
pub fn lines(height: u32, frame: &Frame, lines: &[Line]) -> Result<String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, height)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let mut c = ChartBuilder::on(&root)
            .caption(frame.title, ("sans-serif", 18))
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(65)
            .build_cartesian_2d(frame.x.0..frame.x.1, frame.y.0..frame.y.1)
            .map_err(err)?;
        c.configure_mesh()
            .x_desc(frame.x_desc)
            .y_desc(frame.y_desc)
            .draw()
            .map_err(err)?;
        for line in lines {
            let color = line.color;
            c.draw_series(LineSeries::new(
                line.points.iter().copied(),
                color.stroke_width(1),
            ))
            .map_err(err)?
            .label(line.label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        }
        let labels: Vec<&str> = lines.iter().map(|l| l.label).collect();
        let corner = quiet_corner(
            (frame.x, frame.y),
            c.plotting_area().dim_in_pixel(),
            &labels,
            lines.iter().flat_map(|l| segments(&l.points)),
        );
        c.configure_series_labels()
            .position(corner)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(err)?;
        root.present().map_err(err)?;
    }
    Ok(svg)
}

/// Scatter panels side by side, `height` px high.
pub fn scatter_panels(height: u32, panels: &[Panel]) -> Result<String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, height)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let areas = root.split_evenly((1, panels.len().max(1)));
        for (area, panel) in areas.iter().zip(panels) {
            let f = &panel.frame;
            let mut c = ChartBuilder::on(area)
                .caption(f.title, ("sans-serif", 15))
                .margin(8)
                .x_label_area_size(35)
                .y_label_area_size(55)
                .build_cartesian_2d(f.x.0..f.x.1, f.y.0..f.y.1)
                .map_err(err)?;
            c.configure_mesh()
                .x_desc(f.x_desc)
                .y_desc(f.y_desc)
                .draw()
                .map_err(err)?;
            c.draw_series(
                panel
                    .points
                    .iter()
                    .map(|&(x, y, color)| Circle::new((x, y), panel.radius, color.filled())),
            )
            .map_err(err)?;
            c.draw_series(panel.rings.iter().map(|&(x, y, color)| {
                Circle::new((x, y), panel.radius + 2, color.stroke_width(2))
            }))
            .map_err(err)?;
        }
        root.present().map_err(err)?;
    }
    Ok(svg)
}

/// Width of a character of a bar chart's category names as drawn (the 11 px font scaled into
/// the SVG) \[px\], generous.
const BAR_NAME_PX_PER_CHAR: f64 = 5.5;

/// A bar chart's reference line's name in its legend.
const FLOOR_LABEL: &str = "noise floor";

/// Room under a bar chart's axis that its height already holds for the category names \[px\]:
/// longer names make the chart taller, not the bars shorter.
const BAR_NAME_BAND_PX: u32 = 90;

/// Grouped bars over named categories, with an optional horizontal reference line (a noise
/// floor), `height` px high with names up to `BAR_NAME_BAND_PX` long when turned, and taller
/// by what longer names need.
pub fn bars(
    height: u32,
    title: &str,
    y_desc: &str,
    categories: &[String],
    series: &[Bars],
    floor: Option<f64>,
) -> Result<String> {
    // the rotated category names hang down from the axis: room for the longest, so that
    // none runs off the chart or up into the bars
    let longest = categories
        .iter()
        .map(|c| c.chars().count())
        .max()
        .unwrap_or(0);
    let label_area =
        ((longest as f64 * BAR_NAME_PX_PER_CHAR + 16.0).ceil() as u32).max(BAR_NAME_BAND_PX);
    let height = height + (label_area - BAR_NAME_BAND_PX);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, height)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let (mut y0, y1) = range(
            series
                .iter()
                .flat_map(|s| s.values.iter().copied())
                .chain([0.0])
                .chain(floor),
        );
        y0 = y0.min(0.0);
        let n = categories.len() as f64;
        let mut c = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(10)
            .x_label_area_size(label_area)
            .y_label_area_size(65)
            .build_cartesian_2d(-0.5..(n - 0.5), y0..y1)
            .map_err(err)?;
        c.configure_mesh()
            .disable_x_mesh()
            .x_labels(0)
            .y_desc(y_desc)
            .draw()
            .map_err(err)?;
        // the category names, turned to hang down from the axis below their bars: drawn here
        // anchored at their start (the mesh centres a turned label on its tick, which sends
        // a long one up into the bars)
        let style = TextStyle::from(
            ("sans-serif", 11)
                .into_font()
                .transform(FontTransform::Rotate90),
        )
        .pos(Pos::new(HPos::Left, VPos::Center));
        for (i, name) in categories.iter().enumerate() {
            let (px, py) = c.backend_coord(&(i as f64, y0));
            root.draw(&Text::new(name.clone(), (px, py + 6), style.clone()))
                .map_err(err)?;
        }
        let w = 0.8 / series.len().max(1) as f64;
        // series `j`'s bar over category `i`, as drawn and as the legend must avoid it
        let bar = move |j: usize, (i, v): (usize, &f64)| -> Occupied {
            let x0 = i as f64 - 0.4 + j as f64 * w;
            (x0, x0 + w * 0.9, v.min(0.0), v.max(0.0))
        };
        for (j, s) in series.iter().enumerate() {
            let color = s.color;
            c.draw_series(s.values.iter().enumerate().map(|iv| {
                let (x0, x1, lo, hi) = bar(j, iv);
                Rectangle::new([(x0, lo), (x1, hi)], color.filled())
            }))
            .map_err(err)?
            .label(s.label)
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], color.filled()));
        }
        let floor_line = floor.map(|f| [(-0.5, f), (n - 0.5, f)]);
        if let Some(line) = floor_line {
            c.draw_series(LineSeries::new(line, BLACK.stroke_width(2)))
                .map_err(err)?
                .label(FLOOR_LABEL)
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
        }
        let mut labels: Vec<&str> = series.iter().map(|s| s.label).collect();
        labels.extend(floor.map(|_| FLOOR_LABEL));
        let bar_boxes = series
            .iter()
            .enumerate()
            .flat_map(|(j, s)| s.values.iter().enumerate().map(move |iv| bar(j, iv)));
        let floor_boxes = floor_line.iter().flat_map(|line| segments(line));
        let corner = quiet_corner(
            ((-0.5, n - 0.5), (y0, y1)),
            c.plotting_area().dim_in_pixel(),
            &labels,
            bar_boxes.chain(floor_boxes),
        );
        c.configure_series_labels()
            .position(corner)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(err)?;
        root.present().map_err(err)?;
    }
    Ok(svg)
}

/// Tables of values as coloured cells with their numbers (rows top to bottom), one panel
/// per `(title, values)` stacked vertically, `height` px high in all; the colour runs from
/// white (`good` or better) to red (`bad` or worse).
pub fn heatmaps(
    height: u32,
    rows: &[String],
    columns: &[String],
    panels: &[(&str, Vec<Vec<f64>>)],
    (good, bad): (f64, f64),
) -> Result<String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, height)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let areas = root.split_evenly((panels.len().max(1), 1));
        let (nr, nc) = (rows.len() as f64, columns.len() as f64);
        let label = |names: &[String], x: f64| {
            let i = (x - 0.5).round();
            if (x - 0.5 - i).abs() < 1e-6 && i >= 0.0 && (i as usize) < names.len() {
                names[i as usize].clone()
            } else {
                String::new()
            }
        };
        let reversed: Vec<String> = rows.iter().rev().cloned().collect();
        for (area, (title, values)) in areas.iter().zip(panels) {
            let mut c = ChartBuilder::on(area)
                .caption(*title, ("sans-serif", 16))
                .margin(8)
                .x_label_area_size(25)
                .y_label_area_size(170)
                .build_cartesian_2d(0.0..nc, 0.0..nr)
                .map_err(err)?;
            c.configure_mesh()
                .disable_mesh()
                .x_labels(2 * columns.len() + 1)
                .y_labels(2 * rows.len() + 1)
                .x_label_formatter(&|x| label(columns, *x))
                .y_label_formatter(&|y| label(&reversed, *y))
                .draw()
                .map_err(err)?;
            for (r, row) in values.iter().enumerate() {
                let y = nr - 1.0 - r as f64;
                for (k, v) in row.iter().enumerate() {
                    let x = k as f64;
                    let w = if v.is_finite() {
                        ((v - good) / (bad - good)).clamp(0.0, 1.0)
                    } else {
                        1.0
                    };
                    let fill = RGBColor(255, (255.0 - 170.0 * w) as u8, (255.0 - 200.0 * w) as u8);
                    c.draw_series([Rectangle::new([(x, y), (x + 1.0, y + 1.0)], fill.filled())])
                        .map_err(err)?;
                    let text = if v.is_finite() {
                        format!("{v:.0}")
                    } else {
                        "-".into()
                    };
                    c.draw_series([Text::new(text, (x + 0.4, y + 0.6), ("sans-serif", 12))])
                        .map_err(err)?;
                }
            }
        }
        root.present().map_err(err)?;
    }
    Ok(svg)
}

/// Points with vertical 95 % intervals `(x, y, half_width)` and an optional fitted line
/// through `line = (x0, y0, slope)`, `height` px high.
pub fn intervals(
    height: u32,
    frame: &Frame,
    points: &[(f64, f64, f64)],
    line: Option<(f64, f64, f64)>,
) -> Result<String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, height)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let mut c = ChartBuilder::on(&root)
            .caption(frame.title, ("sans-serif", 16))
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(70)
            .build_cartesian_2d(frame.x.0..frame.x.1, frame.y.0..frame.y.1)
            .map_err(err)?;
        c.configure_mesh()
            .x_desc(frame.x_desc)
            .y_desc(frame.y_desc)
            .draw()
            .map_err(err)?;
        if let Some((x0, y0, slope)) = line {
            let (a, b) = frame.x;
            c.draw_series(LineSeries::new(
                [(a, y0 + slope * (a - x0)), (b, y0 + slope * (b - x0))],
                FINAL_MODEL.stroke_width(2),
            ))
            .map_err(err)?;
        }
        c.draw_series(
            points
                .iter()
                .map(|&(x, y, h)| ErrorBar::new_vertical(x, y - h, y, y + h, MEASURED.filled(), 8)),
        )
        .map_err(err)?;
        root.present().map_err(err)?;
    }
    Ok(svg)
}

/// The range of finite values with 5 % padding ((-1, 1) when there are none).
pub fn range(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = v
        .filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
    if !lo.is_finite() || !hi.is_finite() {
        return (-1.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-9);
    (lo - pad, hi + pad)
}

/// Every `step`-th index of `0..n` so that a plot holds at most `max` points.
pub fn thin(n: usize, max: usize) -> impl Iterator<Item = usize> {
    let step = n.div_ceil(max.max(1)).max(1);
    (0..n).step_by(step)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_chart_is_svg_with_its_labels() {
        let frame = Frame {
            title: "t",
            x_desc: "time [s]",
            y_desc: "force [N]",
            x: (0.0, 1.0),
            y: range([0.0, 2.0].into_iter()),
        };
        let svg = lines(
            300,
            &frame,
            &[Line {
                label: "measured",
                color: MEASURED,
                points: vec![(0.0, 0.0), (1.0, 2.0)],
            }],
        )
        .unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("measured") && svg.contains("time [s]"));
    }

    /// The legend goes to a corner the data leave free: the upper right when it is free, else
    /// the next free corner; with a trace or a steep jump through the upper right, not there.
    #[test]
    fn the_legend_takes_a_corner_the_data_leave_free() {
        let (x, y) = ((0.0, 10.0), (0.0, 10.0));
        let labels = ["measured", "first model"];
        let corner = |pts: &[(f64, f64)]| quiet_corner((x, y), (800, 400), &labels, segments(pts));
        assert!(matches!(
            corner(&[(4.0, 5.0), (6.0, 5.0)]),
            SeriesLabelPosition::UpperRight
        ));
        // a spike beyond the frame through the upper right, no sample inside it: not there
        let spike = [
            (0.0, 5.0),
            (9.6, 5.0),
            (9.7, 2.0),
            (9.7, 11.0),
            (9.8, 5.0),
            (10.0, 5.0),
        ];
        assert!(matches!(corner(&spike), SeriesLabelPosition::UpperLeft));
        // a trace along the top right: the upper left is free
        let top_right: Vec<(f64, f64)> = (0..50).map(|k| (5.0 + 0.1 * k as f64, 9.8)).collect();
        assert!(matches!(corner(&top_right), SeriesLabelPosition::UpperLeft));
        // a trace along the whole top: a lower corner
        let top: Vec<(f64, f64)> = (0..100).map(|k| (0.1 * k as f64, 9.8)).collect();
        assert!(matches!(corner(&top), SeriesLabelPosition::LowerRight));
    }

    /// A bar chart's category names hang down from the axis, starting just below it, never
    /// centred on it (a long one then ran up into the bars and its start was hidden), and the
    /// chart grows to hold the longest (a regime's name with its range, 38 characters, ran
    /// off the bottom when the names' band was capped at half the chart).
    #[test]
    fn bar_names_start_below_the_axis() {
        for long in [
            "baseline (symmetric LuGre)",
            "at oil temperature 23.456..45.678 degC",
        ] {
            let svg = bars(
                360,
                "t",
                "error [%]",
                &[long.to_string(), "+ offset".into()],
                &[Bars {
                    label: "error",
                    color: MEASURED,
                    values: vec![3.0, 1.0],
                }],
                None,
            )
            .unwrap();
            name_below_axis_and_inside(&svg, long);
        }
        // a short name keeps the chart's height
        let svg = bars(360, "t", "e", &["a".into()], &[], None).unwrap();
        assert_eq!(svg_height(&svg), 360.0);
    }

    fn svg_height(svg: &str) -> f64 {
        let i = svg.find(" height=\"").unwrap() + " height=\"".len();
        svg[i..].split('"').next().unwrap().parse().unwrap()
    }

    fn name_below_axis_and_inside(svg: &str, long: &str) {
        let at = svg.find(long).expect("the name is drawn");
        let tag = &svg[svg[..at].rfind("<text").unwrap()..at];
        assert!(tag.contains("text-anchor=\"start\""), "{tag}");
        let number = |key: &str| -> f64 {
            let i = tag.find(key).unwrap() + key.len();
            tag[i..].split('"').next().unwrap().parse().unwrap()
        };
        // the axis is the plot's lowest horizontal line: every name starts below it, and the
        // longest ends inside the chart
        let y = number(" y=\"");
        let axis = svg
            .match_indices("points=\"")
            .filter_map(|(i, k)| {
                let pts: Vec<f64> = svg[i + k.len()..]
                    .split('"')
                    .next()?
                    .split([' ', ','])
                    .filter_map(|v| v.parse().ok())
                    .collect();
                (pts.len() == 4 && pts[1] == pts[3] && pts[2] - pts[0] > 500.0).then_some(pts[1])
            })
            .fold(f64::NEG_INFINITY, f64::max);
        assert!(y > axis && y < axis + 20.0, "name at {y}, axis at {axis}");
        assert!(
            y + BAR_NAME_PX_PER_CHAR * long.len() as f64 <= svg_height(svg),
            "name at {y} runs off the chart"
        );
    }

    #[test]
    fn range_ignores_non_finite_values_and_pads() {
        assert_eq!(range([f64::NAN].into_iter()), (-1.0, 1.0));
        let (lo, hi) = range([0.0, f64::INFINITY, 10.0].into_iter());
        assert!((lo + 0.5).abs() < 1e-12 && (hi - 10.5).abs() < 1e-12);
        assert_eq!(thin(10, 4).collect::<Vec<_>>(), vec![0, 3, 6, 9]);
    }

    /// A panel's rings are drawn hollow and after its dots, so a dot at the same place (a model
    /// meeting a measured breakaway peak) stays visible inside its ring.
    #[test]
    fn rings_are_hollow_and_drawn_over_the_dots() {
        let panel = Panel {
            frame: Frame {
                title: "t",
                x_desc: "x",
                y_desc: "y",
                x: (0.0, 1.0),
                y: (0.0, 1.0),
            },
            points: vec![(0.5, 0.5, FINAL_MODEL)],
            radius: 3,
            rings: vec![(0.5, 0.5, MEASURED)],
        };
        let svg = scatter_panels(200, &[panel]).unwrap();
        let circles: Vec<&str> = svg.lines().filter(|l| l.contains("<circle")).collect();
        assert_eq!(circles.len(), 2, "{circles:?}");
        let (dot, ring) = (circles[0], circles[1]);
        assert!(
            dot.contains("r=\"3\"") && dot.contains("fill=\"#2166AC\""),
            "{dot}"
        );
        assert!(
            ring.contains("r=\"5\"") && ring.contains("fill=\"none\""),
            "{ring}"
        );
        assert!(ring.contains("stroke=\"#282828\""), "{ring}");
    }
}
