//! Helpers of the picture tests: image sizes read back from the bytes.

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
