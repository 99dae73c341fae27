//! The web page: `/` and its script and style, embedded in the binary (no
//! network, no build step), and the shipped example configs it offers.
//! The page talks to the same `/api/v1` as scripts do.

use axum::http::header;
use axum::response::{IntoResponse, Response};

/// The page.
const INDEX_HTML: &str = include_str!("web/index.html");
/// Its script (plain JavaScript, no framework).
const APP_JS: &str = include_str!("web/app.js");
/// Its style.
const APP_CSS: &str = include_str!("web/app.css");

/// The shipped example configs (`configs/*.toml`), by file stem, the
/// default scene first.
pub const EXAMPLES: &[(&str, &str)] = &[
    ("default", include_str!("../../configs/default.toml")),
    ("ap1", include_str!("../../configs/ap1.toml")),
    ("ap2", include_str!("../../configs/ap2.toml")),
    ("ap3", include_str!("../../configs/ap3.toml")),
    ("ap4", include_str!("../../configs/ap4.toml")),
    ("ap5", include_str!("../../configs/ap5.toml")),
    ("circle", include_str!("../../configs/circle.toml")),
    (
        "compare_fracture",
        include_str!("../../configs/compare_fracture.toml"),
    ),
    (
        "compare_shapes",
        include_str!("../../configs/compare_shapes.toml"),
    ),
    ("dense_100k", include_str!("../../configs/dense_100k.toml")),
    (
        "dense_circle",
        include_str!("../../configs/dense_circle.toml"),
    ),
    (
        "dense_l_shape",
        include_str!("../../configs/dense_l_shape.toml"),
    ),
    (
        "dense_limit_pfc",
        include_str!("../../configs/dense_limit_pfc.toml"),
    ),
    (
        "dense_limit_table31",
        include_str!("../../configs/dense_limit_table31.toml"),
    ),
    (
        "dense_optimise_table31",
        include_str!("../../configs/dense_optimise_table31.toml"),
    ),
    (
        "dense_periodic_pfc",
        include_str!("../../configs/dense_periodic_pfc.toml"),
    ),
    (
        "dense_pfc_genesis",
        include_str!("../../configs/dense_pfc_genesis.toml"),
    ),
    (
        "dense_table31",
        include_str!("../../configs/dense_table31.toml"),
    ),
    (
        "dense_table34",
        include_str!("../../configs/dense_table34.toml"),
    ),
    (
        "dense_target",
        include_str!("../../configs/dense_target.toml"),
    ),
    ("fgm_power", include_str!("../../configs/fgm_power.toml")),
    (
        "fgm_sigmoid",
        include_str!("../../configs/fgm_sigmoid.toml"),
    ),
    ("fgm_sizes", include_str!("../../configs/fgm_sizes.toml")),
    (
        "fracture_cell",
        include_str!("../../configs/fracture_cell.toml"),
    ),
    (
        "infeasible_target",
        include_str!("../../configs/infeasible_target.toml"),
    ),
    ("l_shape", include_str!("../../configs/l_shape.toml")),
    (
        "layer_shapes",
        include_str!("../../configs/layer_shapes.toml"),
    ),
    ("loose", include_str!("../../configs/loose.toml")),
    ("mgf1", include_str!("../../configs/mgf1.toml")),
    ("mgf2", include_str!("../../configs/mgf2.toml")),
    ("mgf3", include_str!("../../configs/mgf3.toml")),
    ("narrow", include_str!("../../configs/narrow.toml")),
    (
        "optimise_shapes",
        include_str!("../../configs/optimise_shapes.toml"),
    ),
    (
        "periodic_pfc",
        include_str!("../../configs/periodic_pfc.toml"),
    ),
    (
        "proppant_20_40",
        include_str!("../../configs/proppant_20_40.toml"),
    ),
    (
        "shapes_ellipses",
        include_str!("../../configs/shapes_ellipses.toml"),
    ),
    (
        "shapes_polygons",
        include_str!("../../configs/shapes_polygons.toml"),
    ),
    ("square_100", include_str!("../../configs/square_100.toml")),
    (
        "sweep_shapes",
        include_str!("../../configs/sweep_shapes.toml"),
    ),
    (
        "sweep_wells",
        include_str!("../../configs/sweep_wells.toml"),
    ),
    ("tapered", include_str!("../../configs/tapered.toml")),
    (
        "thesis_fracture",
        include_str!("../../configs/thesis_fracture.toml"),
    ),
    ("trapezoid", include_str!("../../configs/trapezoid.toml")),
    ("wells", include_str!("../../configs/wells.toml")),
    (
        "wells_shapes",
        include_str!("../../configs/wells_shapes.toml"),
    ),
    (
        "wells_exact",
        include_str!("../../configs/wells_exact.toml"),
    ),
    (
        "wide_uniform",
        include_str!("../../configs/wide_uniform.toml"),
    ),
    (
        "window_table31_019",
        include_str!("../../configs/window_table31_019.toml"),
    ),
    (
        "window_table31_030",
        include_str!("../../configs/window_table31_030.toml"),
    ),
];

/// An embedded asset with its content type; revalidated on each load so a
/// new binary's page is never mixed with an old script.
fn asset(content_type: &'static str, body: &'static str) -> Response {
    (
        [
            (header::CONTENT_TYPE, content_type),
            (header::CACHE_CONTROL, "no-cache"),
        ],
        body,
    )
        .into_response()
}

/// `GET /`: the page.
pub async fn index() -> Response {
    asset("text/html; charset=utf-8", INDEX_HTML)
}

/// `GET /app.js`.
pub async fn script() -> Response {
    asset("text/javascript; charset=utf-8", APP_JS)
}

/// `GET /app.css`.
pub async fn style() -> Response {
    asset("text/css; charset=utf-8", APP_CSS)
}

#[cfg(test)]
mod tests {
    use super::EXAMPLES;

    #[test]
    fn every_shipped_config_is_offered_once() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../configs");
        let mut shipped: Vec<String> = std::fs::read_dir(dir)
            .expect("configs/")
            .filter_map(|e| {
                let name = e.ok()?.file_name().into_string().ok()?;
                name.strip_suffix(".toml").map(str::to_owned)
            })
            .collect();
        shipped.sort();
        let mut offered: Vec<String> = EXAMPLES.iter().map(|(n, _)| (*n).to_owned()).collect();
        assert_eq!(offered[0], "default");
        offered.sort();
        assert_eq!(offered, shipped);
    }
}
