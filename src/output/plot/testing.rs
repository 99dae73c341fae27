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

/// A text of an SVG chart: where it is anchored (x), how (`text-anchor`), its
/// font size (px) and its content.
#[derive(Debug)]
pub(super) struct SvgText {
    pub x: f64,
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
                anchor: attribute("text-anchor"),
                size: number("font-size"),
                text: element[open..close].trim().to_owned(),
            }
        })
        .collect()
}
