//! PNG text, laid out glyph by glyph as the SVG's text is: [`Glyphs`].
//!
//! plotters 0.3.7 draws ab_glyph text with each glyph's outline put at the
//! pen position without its left side bearing, and the pen cut to whole
//! pixels: a narrow letter moves left onto the one before and leaves a gap
//! after it ("clay" read "day", "achieved" read "achi eved"). [`Glyphs`]
//! wraps a bitmap backend and draws text itself with ab_glyph: each glyph
//! at its kerned pen position plus its bearing (sub-pixel), at the size and
//! anchor the SVG backend writes (`font-size` = size / 1.24; baseline 0.76 em
//! below a top anchor, 0.5 ex below a centre one, 0.5 ex above a bottom one).
//! Text sizes for layout stay plotters' own estimates, as in the SVG.

use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, Glyph, PxScale, ScaleFont, point};
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
};

use super::chart::FONT;

/// The bundled font, parsed once.
fn font() -> &'static FontRef<'static> {
    static PARSED: OnceLock<FontRef<'static>> = OnceLock::new();
    // The bundled bytes are a valid font (checked by chart's tests).
    PARSED.get_or_init(|| FontRef::try_from_slice(FONT).expect("the bundled font parses"))
}

/// Ratio of plotters' text size to the SVG's `font-size` (plotters-svg's own).
const SVG_EM: f64 = 1.24;

/// `text` laid out from the origin on its baseline, in pixels of an em of
/// `em`: its glyphs and its advance width.
pub(super) fn layout(text: &str, em: f32) -> (Vec<Glyph>, f32) {
    let font = font();
    let units = font.units_per_em().unwrap_or(2048.0);
    let scaled = font.as_scaled(PxScale::from(em * font.height_unscaled() / units));
    let mut pen = 0.0f32;
    let mut previous = None;
    let glyphs = text
        .chars()
        .map(|c| {
            let id = scaled.glyph_id(c);
            if let Some(before) = previous {
                pen += scaled.kern(before, id);
            }
            previous = Some(id);
            let glyph = id.with_scale_and_position(scaled.scale(), point(pen, 0.0));
            pen += scaled.h_advance(id);
            glyph
        })
        .collect();
    (glyphs, pen)
}

/// A drawing backend that draws text as [the module](self) says and
/// everything else as the backend it wraps.
pub(super) struct Glyphs<B>(pub(super) B);

impl<B: DrawingBackend> DrawingBackend for Glyphs<B> {
    type ErrorType = B::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.0.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_path(path, style)
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_circle(center, radius, style, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.fill_polygon(vert, style)
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.blit_bitmap(pos, size, src)
    }

    fn draw_text<TStyle: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &TStyle,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let em = (style.size() / SVG_EM) as f32;
        let (glyphs, width) = layout(text, em);
        // Half the height of an "x" (its top lies at −x-height).
        let half_ex = layout("x", em)
            .0
            .into_iter()
            .find_map(|g| font().outline_glyph(g))
            .map_or(0.25 * em, |x| -0.5 * x.px_bounds().min.y);
        let anchor = style.anchor();
        let dx = match anchor.h_pos {
            HPos::Left => 0.0,
            HPos::Center => -0.5 * width,
            HPos::Right => -width,
        };
        let baseline = match anchor.v_pos {
            VPos::Top => 0.76 * em,
            VPos::Center => half_ex,
            VPos::Bottom => -half_ex,
        };
        let turn = style.transform();
        let mut drawn = Ok(());
        for mut glyph in glyphs {
            glyph.position = point(glyph.position.x + dx, baseline);
            let Some(outline) = font().outline_glyph(glyph) else {
                continue;
            };
            let corner = outline.px_bounds().min;
            outline.draw(|x, y, cover| {
                if drawn.is_err() || cover <= 0.0 {
                    return;
                }
                let (x, y) = turn.transform(corner.x as i32 + x as i32, corner.y as i32 + y as i32);
                let ink = BackendColor {
                    alpha: color.alpha * f64::from(cover.min(1.0)),
                    rgb: color.rgb,
                };
                drawn = self.0.draw_pixel((pos.0 + x, pos.1 + y), ink);
            });
        }
        drawn
    }
}

#[cfg(test)]
mod tests {
    use plotters::prelude::*;
    use plotters::style::text_anchor::Pos;

    use super::*;
    use crate::output::plot::chart::{FAMILY, register_font};

    /// `word` drawn black on white at `size` (plotters' text size) on a
    /// bitmap, through `Glyphs` or plotters' own text path: per pixel
    /// column, whether it holds ink.
    fn ink_columns(word: &str, size: f64, ours: bool) -> Vec<bool> {
        register_font();
        let (w, h) = (400u32, 80u32);
        let mut rgb = vec![255u8; (w * h * 3) as usize];
        {
            let style = (FAMILY, size)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Left, VPos::Center));
            let text = Text::new(word.to_owned(), (20, 40), style);
            let bitmap = BitMapBackend::with_buffer(&mut rgb, (w, h));
            if ours {
                let root = Glyphs(bitmap).into_drawing_area();
                root.draw(&text).expect("draws");
            } else {
                let root = bitmap.into_drawing_area();
                root.draw(&text).expect("draws");
            }
        }
        (0..w as usize)
            .map(|x| (0..h as usize).any(|y| rgb[3 * (y * w as usize + x)] < 150))
            .collect()
    }

    /// Column spans `[start, end)` of the runs of inked columns (letters
    /// that do not touch each give one).
    fn runs(columns: &[bool]) -> Vec<(usize, usize)> {
        let mut runs: Vec<(usize, usize)> = Vec::new();
        for (i, &ink) in columns.iter().enumerate() {
            match runs.last_mut() {
                Some(run) if ink && run.1 == i => run.1 = i + 1,
                _ if ink => runs.push((i, i + 1)),
                _ => {}
            }
        }
        runs
    }

    /// Each letter of a word is its own glyph box, where the font's layout
    /// puts it, and the letters sit as close as the font sets them: "clay"
    /// reads "clay", not "day", and "achieved" has no hole after its "i".
    #[test]
    fn png_letters_neither_merge_nor_split() {
        for size in [14.0, 16.0, 22.0] {
            for word in ["clay", "achieved", "sand"] {
                let runs = runs(&ink_columns(word, size, true));
                assert_eq!(runs.len(), word.len(), "{word} at {size}: {runs:?}");
                // Between letters of a word the blank is a fraction of the size.
                let widest = runs.windows(2).map(|w| w[1].0 - w[0].1).max();
                assert!(
                    widest.is_some_and(|gap| gap as f64 <= 0.2 * size),
                    "{word} at {size}: {runs:?}"
                );
                // Each glyph's ink spans the columns of its outline laid out
                // from x = 20 (to a pixel: anti-aliased edges).
                let (glyphs, _) = layout(word, (size / SVG_EM) as f32);
                for (glyph, &(start, end)) in glyphs.into_iter().zip(&runs) {
                    let outline = font().outline_glyph(glyph).expect("a letter has ink");
                    let bounds = outline.px_bounds();
                    let (lo, hi) = (20.0 + bounds.min.x, 20.0 + bounds.max.x);
                    assert!(
                        (start as f32 - lo).abs() <= 1.0 && (end as f32 - hi).abs() <= 1.0,
                        "{word} at {size}: ink {start}..{end}, outline {lo}..{hi}"
                    );
                }
            }
        }
    }

    /// What the test above catches: plotters' own text path merges "cl"
    /// and "hi". Should this fail, plotters has mended its text and
    /// `Glyphs` can go.
    #[test]
    fn plotters_own_text_path_merges_letters() {
        for word in ["clay", "achieved"] {
            let runs = runs(&ink_columns(word, 14.0, false));
            assert!(runs.len() < word.len(), "{word}: {runs:?}");
        }
    }

    /// The drawn word is as wide as its layout, where the SVG puts it.
    #[test]
    fn text_is_anchored_as_in_the_svg() {
        let columns = ink_columns("achieved", 22.0, true);
        let first = columns.iter().position(|&c| c).expect("ink");
        let last = columns.iter().rposition(|&c| c).expect("ink");
        let (_, width) = layout("achieved", (22.0 / SVG_EM) as f32);
        assert!((19..=22).contains(&first), "starts at {first}");
        assert!(
            ((last + 1 - 20) as f32 - width).abs() <= 2.0,
            "{} px wide, laid out {width}",
            last + 1 - 20
        );
    }
}
