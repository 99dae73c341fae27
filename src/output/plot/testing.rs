//! Helpers of the picture tests: image sizes, pixels and texts read back
//! from the bytes.

/// Width and height of an SVG document's root element, after checking it is whole.
pub(super) fn svg_size(svg: &str) -> (u32, u32) {
    assert!(
        svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"),
        "{svg}"
    );
    let attribute = |name: &str| -> u32 {
        let start = svg.find(&format!("{name}=\"")).expect(name) + name.len() + 2;
        let end = start + svg[start..].find('"').expect("closing quote");
        svg[start..end].parse().expect("a number")
    };
    (attribute("width"), attribute("height"))
}

/// Width and height of a PNG, after checking its signature and header.
pub(super) fn png_size(png: &[u8]) -> (u32, u32) {
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let reader = png::Decoder::new(png).read_info().expect("a PNG header");
    (reader.info().width, reader.info().height)
}

/// The pixels of an 8-bit RGB PNG, row by row from the top, and its size.
pub(super) fn png_rgb(png: &[u8]) -> (Vec<u8>, (u32, u32)) {
    let mut reader = png::Decoder::new(png).read_info().expect("a PNG header");
    let mut rgb = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut rgb).expect("a frame");
    assert_eq!(info.color_type, png::ColorType::Rgb);
    rgb.truncate(info.buffer_size());
    (rgb, (info.width, info.height))
}

/// A text of an SVG chart: where it is anchored (x, y), how (`text-anchor`,
/// and `dy`: top, centre or bottom), its font size (px) and its content.
#[derive(Debug)]
pub(super) struct SvgText {
    pub x: f64,
    pub y: f64,
    pub dy: String,
    pub anchor: String,
    pub size: f64,
    pub text: String,
}

impl SvgText {
    /// Its horizontal extent (px) as drawn with the bundled font.
    pub(super) fn extent(&self) -> (f64, f64) {
        let width = f64::from(super::text::layout(&self.text, self.size as f32).1);
        let left = match self.anchor.as_str() {
            "middle" => self.x - 0.5 * width,
            "end" => self.x - width,
            _ => self.x,
        };
        (left, left + width)
    }

    /// Its vertical extent (px): a font size from its anchor, on the side
    /// `dy` says (plotters' 0.76em top, 0.5ex centre, −0.5ex bottom).
    pub(super) fn vertical(&self) -> (f64, f64) {
        match self.dy.as_str() {
            "0.76em" => (self.y, self.y + self.size),
            "0.5ex" => (self.y - 0.5 * self.size, self.y + 0.5 * self.size),
            _ => (self.y - self.size, self.y),
        }
    }
}

/// Every `<text>` element of an SVG document written by plotters.
pub(super) fn svg_texts(svg: &str) -> Vec<SvgText> {
    svg.split("<text ")
        .skip(1)
        .map(|element| {
            let attribute = |name: &str| -> String {
                let key = format!(" {name}=\"");
                let start = format!(" {element}").find(&key).expect(name) + key.len() - 1;
                let end = start + element[start..].find('"').expect("closing quote");
                element[start..end].to_owned()
            };
            let number = |name: &str| attribute(name).parse::<f64>().expect("a number");
            let open = element.find('>').expect("tag end") + 1;
            let close = element.find("</text>").expect("closing tag");
            SvgText {
                x: number("x"),
                y: number("y"),
                dy: if element.contains(" dy=\"") {
                    attribute("dy")
                } else {
                    String::new()
                },
                anchor: attribute("text-anchor"),
                size: number("font-size"),
                text: element[open..close].trim().to_owned(),
            }
        })
        .collect()
}

/// Where an SVG chart draws data: every circle's centre, and a point every
/// pixel along every polyline at least 2 px wide (data lines; axes and
/// the mesh are 1 px).
pub(super) fn svg_marks(svg: &str) -> Vec<(f64, f64)> {
    let attribute = |element: &str, name: &str| -> Option<String> {
        let key = format!(" {name}=\"");
        let start = element.find(&key)? + key.len();
        let end = start + element[start..].find('"')?;
        Some(element[start..end].to_owned())
    };
    let number = |element: &str, name: &str| -> f64 {
        attribute(element, name)
            .and_then(|v| v.parse().ok())
            .expect("a number")
    };
    let mut marks: Vec<(f64, f64)> = svg
        .split("<circle")
        .skip(1)
        .map(|e| (number(e, "cx"), number(e, "cy")))
        .collect();
    for e in svg.split("<polyline").skip(1) {
        let e = &e[..e.find("/>").expect("element end")];
        if attribute(e, "stroke-width").is_none_or(|w| w.parse::<f64>().unwrap_or(0.0) < 2.0) {
            continue;
        }
        let points: Vec<(f64, f64)> = attribute(e, "points")
            .expect("points")
            .split_whitespace()
            .map(|p| {
                let (x, y) = p.split_once(',').expect("x,y");
                (x.parse().expect("x"), y.parse().expect("y"))
            })
            .collect();
        marks.extend(points.first());
        for pair in points.windows(2) {
            let ((x0, y0), (x1, y1)) = (pair[0], pair[1]);
            let steps = (x1 - x0).abs().max((y1 - y0).abs()).ceil().max(1.0);
            marks.extend((1..=steps as usize).map(|k| {
                let t = k as f64 / steps;
                (x0 + t * (x1 - x0), y0 + t * (y1 - y0))
            }));
        }
    }
    marks
}

/// The box (left, top, right, bottom; px) the legend of an SVG chart
/// takes: the extents of the texts `labels`, and 40 px left of them for
/// their swatches.
pub(super) fn legend_box(svg: &str, labels: &[String]) -> (f64, f64, f64, f64) {
    let texts: Vec<SvgText> = svg_texts(svg)
        .into_iter()
        .filter(|t| labels.contains(&t.text))
        .collect();
    assert_eq!(texts.len(), labels.len(), "every legend text is drawn once");
    texts.iter().fold(
        (
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ),
        |(l, t, r, b), text| {
            let ((x0, x1), (y0, y1)) = (text.extent(), text.vertical());
            (l.min(x0 - 40.0), t.min(y0), r.max(x1), b.max(y1))
        },
    )
}

/// Panics naming the first data mark of `svg` under the box its legend of
/// `labels` takes.
pub(super) fn assert_legend_hides_nothing(svg: &str, labels: &[String]) {
    let (l, t, r, b) = legend_box(svg, labels);
    let marks = svg_marks(svg);
    assert!(!marks.is_empty(), "data are drawn");
    for (x, y) in marks {
        assert!(
            !(l..=r).contains(&x) || !(t..=b).contains(&y),
            "a mark at ({x}, {y}) lies under the legend ({l}, {t})–({r}, {b})"
        );
    }
}

/// The legend's labels of a line chart: its series that have a name.
pub(super) fn legend_labels(chart: &super::chart::LineChart) -> Vec<String> {
    chart
        .series
        .iter()
        .map(|s| s.name.clone())
        .filter(|n| !n.is_empty())
        .collect()
}
