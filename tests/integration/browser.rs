//! The web page of `gapack serve` in a real browser: headless Chromium
//! driven over WebDriver against the real server on a loopback port.
//!
//! Needs Debian's `chromium` and `chromium-driver` (or `GAPACK_CHROMIUM` and
//! `GAPACK_CHROMEDRIVER`); without them each test says how to run it and
//! passes, unless `GAPACK_BROWSER_TESTS=required` (as CI sets it), when it
//! fails. Screenshots go to `target/tmp/screenshots/` (or
//! `GAPACK_SCREENSHOTS`).

use crate::common;
use crate::common::webdriver;

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Duration;

use common::scratch;
use common::server::{Server, agent};
use serde_json::{Value, json};
use webdriver::Browser;

/// One browser at a time: each is a few hundred MB and the machine has two cores.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

const DESKTOP: (u32, u32) = (1280, 800);
const PHONE: (u32, u32) = (390, 844);

/// Whether the browser tests can run; if not, say why and how.
fn browser_here() -> bool {
    match webdriver::missing() {
        None => true,
        Some(what) => {
            let how = "install Debian's chromium and chromium-driver \
                       (apt-get install -y chromium chromium-driver), then \
                       `cargo test --test integration browser::`";
            assert!(
                std::env::var("GAPACK_BROWSER_TESTS").as_deref() != Ok("required"),
                "browser tests required, but {what} missing: {how}"
            );
            eprintln!("browser test skipped: {what} missing; {how}");
            false
        }
    }
}

fn shots() -> PathBuf {
    std::env::var_os("GAPACK_SCREENSHOTS").map_or_else(
        || Path::new(env!("CARGO_TARGET_TMPDIR")).join("screenshots"),
        PathBuf::from,
    )
}

/// `GET` through the API: status and body.
fn get(server: &Server, path: &str) -> (u16, Vec<u8>) {
    let mut r = agent().get(server.url(path)).call().expect("GET");
    let status = r.status().as_u16();
    let body = r
        .body_mut()
        .with_config()
        .limit(256 << 20)
        .read_to_vec()
        .expect("body");
    (status, body)
}

/// Submit `config` as `kind` through the API; the job's id.
fn submit(server: &Server, kind: &str, config: &str, seed: u64) -> String {
    let mut r = agent()
        .post(server.url(&format!("/api/v1/jobs?kind={kind}&seed={seed}")))
        .header("Content-Type", "application/toml")
        .send(config)
        .expect("POST");
    let body: Value =
        serde_json::from_str(&r.body_mut().read_to_string().expect("body")).expect("JSON");
    assert_eq!(r.status().as_u16(), 201, "{body}");
    body["id"].as_str().expect("id").to_owned()
}

/// The job's state through the API.
fn state(server: &Server, id: &str) -> String {
    let (_, body) = get(server, &format!("/api/v1/jobs/{id}"));
    let job: Value = serde_json::from_slice(&body).expect("JSON");
    job["state"].as_str().unwrap_or_default().to_owned()
}

/// The text of element `css`, if it exists and is shown.
fn shown_text(browser: &Browser, css: &str) -> Option<String> {
    let v = browser.run(
        "const e = document.querySelector(arguments[0]); \
         return e && !e.closest('[hidden]') ? e.textContent : null;",
        &[json!(css)],
    );
    v.as_str().map(str::to_owned)
}

/// Points of the convergence chart drawn so far (none before it is drawn).
fn chart_points(browser: &Browser) -> Option<u64> {
    browser
        .run(
            "return Number(document.getElementById('convergence').dataset.points || 0);",
            &[],
        )
        .as_u64()
}

/// Disks of the packing canvas once it is drawn.
fn drawn_disks(browser: &Browser) -> Option<String> {
    browser
        .run(
            "return document.getElementById('packing').dataset.disks || null;",
            &[],
        )
        .as_str()
        .map(str::to_owned)
}

/// Pixels of canvas `css` that are not white.
fn inked(browser: &Browser, css: &str) -> u64 {
    browser
        .run(
            "const c = document.querySelector(arguments[0]); \
             const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data; \
             let n = 0; for (let i = 0; i < d.length; i += 4) \
               if (d[i] < 250 || d[i + 1] < 250 || d[i + 2] < 250) n++; \
             return n;",
            &[json!(css)],
        )
        .as_u64()
        .unwrap_or(0)
}

/// The page fits its width (no sideways scrolling), and every control has a
/// name a screen reader can say.
fn usable(browser: &Browser, page: &str) {
    let overflow = browser.run(
        "return document.documentElement.scrollWidth - window.innerWidth;",
        &[],
    );
    let culprits = browser.run(
        "return [...document.querySelectorAll('body *')] \
           .filter(e => !e.closest('[hidden]') && e.getBoundingClientRect().right > window.innerWidth + 1 \
                        && !e.parentElement.closest('.table-wrap')) \
           .map(e => e.tagName + '#' + e.id + '.' + e.className).slice(0, 8);",
        &[],
    );
    assert!(
        overflow.as_i64().unwrap_or(0) <= 1,
        "{page}: wider than the window by {overflow} px: {culprits}"
    );
    let unnamed = browser.run(
        "return [...document.querySelectorAll('input, select, textarea, button, canvas[tabindex]')] \
           .filter(e => !e.closest('[hidden]')) \
           .filter(e => !(e.labels && e.labels.length) && !e.getAttribute('aria-label') \
                        && !e.getAttribute('aria-labelledby') && !e.textContent.trim()) \
           .map(e => e.id || e.outerHTML.slice(0, 60));",
        &[],
    );
    assert_eq!(unnamed, json!([]), "{page}: controls without a name");
}

#[test]
fn an_example_is_validated_submitted_followed_and_its_packing_shown() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    if !browser_here() {
        return;
    }
    let dir = scratch("browser-example");
    let server = Server::start(&dir.join("data"), &[]);
    let browser = Browser::start(&dir.join("downloads"), DESKTOP);
    browser.goto(&server.url("/"));

    // Pick an example; validate it.
    let example = browser.find("#example option[value='dense_target']");
    browser.click(&example);
    let editor_text = browser.run("return document.getElementById('config').value;", &[]);
    assert!(
        editor_text
            .as_str()
            .is_some_and(|t| t.contains("target_porosity = 0.20")),
        "the editor holds the example: {editor_text}"
    );
    // Edit it as a user would: a looser target than any packing reaches, so
    // the search runs its twelve generations (a target below the advancing
    // front's range would be packed by densify at once, without a search).
    browser.run(
        "const e = document.getElementById('config'); \
         e.value = e.value.replace('target_porosity = 0.20', \
           'target_porosity = 0.95\\ngenerations = 12\\nstagnation = 100'); \
         e.dispatchEvent(new Event('input'));",
        &[],
    );
    browser.click(&browser.find("#kind option[value='optimise']"));
    browser.click(&browser.find("#validate"));
    let estimates = browser.wait("the estimates", || shown_text(&browser, "#estimates"));
    assert!(estimates.contains("disks"), "{estimates}");
    assert!(estimates.contains("memory at most"), "{estimates}");
    assert!(estimates.contains("time about"), "{estimates}");
    let plan = shown_text(&browser, "#validation pre").expect("the plan");
    assert!(plan.contains("optimise"), "{plan}");
    usable(&browser, "new job");
    browser.screenshot(&shots().join("new-job.png"));

    // Submit; the job page follows it.
    browser.click(&browser.find("#submit"));
    let id = browser.wait("the job page", || {
        let hash = browser.run("return location.hash;", &[]);
        hash.as_str()?.strip_prefix("#/job/").map(str::to_owned)
    });
    // The convergence chart gains points while the search runs.
    let mut seen = Vec::new();
    browser.wait("the search to end", || {
        let points = chart_points(&browser).unwrap_or(0);
        if seen.last() != Some(&points) {
            seen.push(points);
        }
        (shown_text(&browser, "#job-state").as_deref() == Some("succeeded")).then_some(())
    });
    assert!(
        seen.windows(2).all(|w| w[0] < w[1]) && seen.iter().filter(|&&p| p > 0).count() >= 3,
        "the chart grew point by point: {seen:?}"
    );
    assert!(inked(&browser, "#convergence") > 1000);

    // The packing is drawn from its data; hovering a disk gives its data.
    browser.wait("the packing drawn", || drawn_disks(&browser));
    assert!(inked(&browser, "#packing") > 10_000);
    let (_, csv) = get(&server, &format!("/api/v1/jobs/{id}/files/packing.csv"));
    let csv = String::from_utf8(csv).expect("UTF-8");
    let first: Vec<f64> = csv
        .lines()
        .nth(1)
        .expect("a disk")
        .split(',')
        .map(|v| v.parse().expect("number"))
        .collect();
    let at = browser.run("return window.gapackViewer.centre(0);", &[]);
    let (x, y) = (at[0].as_f64().expect("x"), at[1].as_f64().expect("y"));
    browser.run(
        "document.getElementById('packing').scrollIntoView({block: 'center'});",
        &[],
    );
    let at = browser.run("return window.gapackViewer.centre(0);", &[]);
    let (x, y) = (at[0].as_f64().unwrap_or(x), at[1].as_f64().unwrap_or(y));
    browser.pointer_to(x, y);
    let hover = browser.wait("the hover box", || shown_text(&browser, "#hover"));
    assert!(
        hover.starts_with("id 0 ·")
            && hover.contains(&format!("x {:.4}", first[1]))
            && hover.contains(&format!("y {:.4}", first[2]))
            && hover.contains(&format!("r {:.4} mm", first[3])),
        "{hover} against {first:?}"
    );
    // The grading chart, the porosity map and the convergence chart, the summary.
    for chart in ["psd.svg", "porosity_map.svg", "convergence.svg"] {
        let loaded = browser.wait(chart, || {
            browser
                .run(
                    "const i = [...document.querySelectorAll('#charts img')] \
                       .find(i => i.src.endsWith(arguments[0])); \
                     return i && i.complete && i.naturalWidth > 0 ? i.naturalWidth : null;",
                    &[json!(chart)],
                )
                .as_u64()
        });
        assert!(loaded > 100, "{chart}");
    }
    let porosity = browser.wait("the summary table", || {
        shown_text(&browser, "#summary").filter(|t| t.contains("porosity"))
    });
    assert!(porosity.contains("psd_ks"), "{porosity}");
    browser.screenshot(&shots().join("job-hover.png"));
    browser.run("window.scrollTo(0, 0);", &[]);
    browser.screenshot(&shots().join("job-optimise.png"));
    // Keyboard: the canvas takes focus, + zooms in (fewer disks in view), 0 fits again.
    browser.run("document.getElementById('packing').focus();", &[]);
    let drawn = || {
        browser
            .run(
                "return Number(document.getElementById('packing').dataset.drawn);",
                &[],
            )
            .as_u64()
            .unwrap_or(0)
    };
    let all = drawn();
    for _ in 0..4 {
        browser.press("+");
    }
    browser.wait("zoomed in", || (drawn() < all).then_some(()));
    browser.press("0");
    browser.wait("fitted again", || (drawn() == all).then_some(()));

    // Download packing.csv from its link: the API's bytes.
    browser.run(
        "[...document.querySelectorAll('#files a')].find(a => a.textContent === 'packing.csv').click();",
        &[],
    );
    let downloaded = browser.wait("the download", || {
        let path = browser.downloads.join("packing.csv");
        std::fs::read(&path).ok().filter(|b| b.len() == csv.len())
    });
    assert_eq!(downloaded, csv.as_bytes(), "downloaded packing.csv");

    // At phone width the job page still fits.
    browser.window(PHONE.0, PHONE.1);
    std::thread::sleep(Duration::from_millis(300));
    usable(&browser, "job at phone width");
    browser.screenshot(&shots().join("job-phone.png"));
}

/// `packing.csv`'s first particle: column name to cell.
fn first_row(csv: &str) -> std::collections::HashMap<String, String> {
    let mut lines = csv.lines();
    let header = lines.next().expect("a header").split(',');
    let row = lines.next().expect("a particle").split(',');
    header
        .map(str::to_owned)
        .zip(row.map(str::to_owned))
        .collect()
}

/// The number after `label ` in the hover box's `words`.
fn hovered(words: &str, label: &str) -> f64 {
    let after = words
        .split(" · ")
        .find_map(|part| part.strip_prefix(label)?.strip_prefix(' '))
        .unwrap_or_else(|| panic!("no {label} in {words}"));
    after
        .trim_end_matches(['°', ' ', 'm'])
        .parse()
        .unwrap_or_else(|_| panic!("{label}: {after:?} in {words}"))
}

#[test]
fn a_shapes_packing_is_drawn_and_hover_gives_angle_aspect_and_sphericity() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    if !browser_here() {
        return;
    }
    let dir = scratch("browser-shapes");
    let server = Server::start(&dir.join("data"), &[]);
    let browser = Browser::start(&dir.join("downloads"), DESKTOP);
    let square = "[domain]\nshape = \"rectangle\"\nwidth = 15\nheight = 15\n[grading]\nuniform = [1.0, 2.0]\n";
    let ellipses = submit(
        &server,
        "pack",
        &format!(
            "{square}[shape]\nkind = \"superellipse\"\naspect = 1.5\norientation = \"random\"\n"
        ),
        3,
    );
    let polygons = submit(
        &server,
        "pack",
        &format!(
            "{square}[shape]\nkind = \"polygon\"\norientation = \"random\"\n\
             [[shape.templates]]\nvertices = [[0, 0.8], [0.8, 0], [2.2, 0], [3, 0.8], [2.2, 1.6], [0.8, 1.6]]\n\
             rounding = 0.15\nshare = 1.0\n"
        ),
        3,
    );
    for (id, name) in [(&ellipses, "ellipses"), (&polygons, "polygons")] {
        browser.wait("the pack", || {
            (state(&server, id) == "succeeded").then_some(())
        });
        browser.goto(&server.url(&format!("/#/job/{id}")));
        browser.wait("the packing drawn", || drawn_disks(&browser));
        assert!(
            inked(&browser, "#packing") > 10_000,
            "{name}: the canvas is drawn"
        );
        let label = browser.run(
            "return document.getElementById('packing').getAttribute('aria-label');",
            &[],
        );
        assert!(
            label
                .as_str()
                .is_some_and(|l| l.contains("hover a particle")),
            "{name}: {label}"
        );
        // Hovering the first particle's centre: its row's values.
        let (_, csv) = get(&server, &format!("/api/v1/jobs/{id}/files/packing.csv"));
        let row = first_row(&String::from_utf8(csv).expect("UTF-8"));
        let number = |column: &str| -> f64 { row[column].parse().expect("a number") };
        let outline = if name == "ellipses" {
            gapack::Outline::superellipse(number("a"), number("b"), number("alpha"), number("beta"))
                .expect("a superellipse")
        } else {
            let vertices: Vec<gapack::Point> = row["vertices"]
                .split(';')
                .map(|v| {
                    let (x, y) = v.split_once(' ').expect("x y");
                    gapack::Point::new(x.parse().expect("x"), y.parse().expect("y"))
                })
                .collect();
            gapack::Outline::polygon(0, &vertices, number("rounding")).expect("a polygon")
        };
        browser.run(
            "document.getElementById('packing').scrollIntoView({block: 'center'});",
            &[],
        );
        let at = browser.run("return window.gapackViewer.centre(0);", &[]);
        browser.pointer_to(at[0].as_f64().expect("x"), at[1].as_f64().expect("y"));
        let words = browser.wait("the hover box", || shown_text(&browser, "#hover"));
        assert!(words.starts_with("id 0 ·"), "{name}: {words}");
        assert!(
            words.contains(&format!("r {:.4} mm", number("r"))),
            "{name}: {words} against r {}",
            row["r"]
        );
        let degrees = number("angle") * 180.0 / std::f64::consts::PI;
        assert!(
            words.contains(&format!("angle {degrees:.2}°")),
            "{name}: {words} against angle {}",
            row["angle"]
        );
        // The library's measures, to the three decimals shown.
        let aspect = outline.aspect();
        if name == "ellipses" {
            let (a, b) = (number("a"), number("b"));
            assert!((aspect - a.max(b) / a.min(b)).abs() < 1e-9, "{aspect}");
        }
        for (label, want) in [
            ("aspect", aspect),
            ("sphericity", gapack::sphericity(&outline)),
        ] {
            let got = hovered(&words, label);
            assert!(
                (got - want).abs() <= 6e-4,
                "{name}: {label} {got} against {want}: {words}"
            );
        }
        browser.screenshot(&shots().join(format!("job-{name}.png")));
    }
    // At phone width a particle's longer words wrap within the canvas.
    browser.window(PHONE.0, PHONE.1);
    std::thread::sleep(Duration::from_millis(300));
    browser.run(
        "document.getElementById('packing').scrollIntoView({block: 'center'});",
        &[],
    );
    let at = browser.run("return window.gapackViewer.centre(0);", &[]);
    browser.pointer_to(at[0].as_f64().expect("x"), at[1].as_f64().expect("y"));
    let words = browser.wait("the hover box", || {
        shown_text(&browser, "#hover").filter(|w| w.contains("sphericity"))
    });
    usable(
        &browser,
        &format!("a particle hovered at phone width ({words})"),
    );
    browser.screenshot(&shots().join("job-shapes-phone.png"));
    browser.window(DESKTOP.0, DESKTOP.1);
    // The jobs list counts particles, not disks.
    browser.goto(&server.url("/#/jobs"));
    let words = browser.wait("the jobs listed", || {
        shown_text(&browser, "#jobs-table tbody").filter(|t| t.matches("porosity").count() == 2)
    });
    assert!(
        words.contains(" particles") && !words.contains(" disks"),
        "{words}"
    );
}

#[test]
fn a_long_optimise_is_cancelled_and_keeps_its_best_packing() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    if !browser_here() {
        return;
    }
    let dir = scratch("browser-cancel");
    let server = Server::start(&dir.join("data"), &[]);
    let browser = Browser::start(&dir.join("downloads"), DESKTOP);
    let config = "seed = 5\n[domain]\nshape = \"rectangle\"\nwidth = 80\nheight = 80\n\
                  [grading]\nuniform = [1.0, 2.0]\n[optimise]\ntarget_porosity = 0.95\n\
                  population = 8\ngenerations = 5000\nstagnation = 10000\n";
    let id = submit(&server, "optimise", config, 2);
    browser.goto(&server.url(&format!("/#/job/{id}")));
    browser.wait("two generations drawn", || {
        let n = chart_points(&browser)?;
        (n >= 2).then_some(())
    });
    browser.click(&browser.find("#cancel"));
    browser.wait("cancelled", || {
        (shown_text(&browser, "#job-state").as_deref() == Some("cancelled")).then_some(())
    });
    assert_eq!(state(&server, &id), "cancelled");
    // The best packing was kept: drawn, and listed with the other files.
    browser.wait("the kept packing drawn", || drawn_disks(&browser));
    assert!(inked(&browser, "#packing") > 10_000);
    let files = browser.wait("the files", || {
        shown_text(&browser, "#files").filter(|t| t.contains("packing.csv"))
    });
    assert!(files.contains("convergence.csv"), "{files}");
    browser.screenshot(&shots().join("job-cancelled.png"));
}

#[test]
fn a_config_error_is_shown_at_its_line() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    if !browser_here() {
        return;
    }
    let dir = scratch("browser-error");
    let server = Server::start(&dir.join("data"), &[]);
    let browser = Browser::start(&dir.join("downloads"), DESKTOP);
    browser.goto(&server.url("/"));
    browser.find("#example option[value='default']");
    let editor = browser.find("#config");
    browser.clear(&editor);
    browser.type_text(
        &editor,
        "seed = 1\n[domain]\nshape = \"rectangle\"\nwidth = -5\nheight = 10\n[grading]\nconstant = 1.0\n",
    );
    browser.click(&browser.find("#validate"));
    let error = browser.wait("the error", || shown_text(&browser, "#config-error"));
    assert!(
        error.starts_with("Line 4, column 9 · domain.width")
            && error.contains("must be a positive finite number"),
        "{error}"
    );
    let marked = browser.run(
        "return [...document.querySelectorAll('#gutter span.bad')].map(s => s.textContent);",
        &[],
    );
    assert_eq!(marked, json!(["4"]));
    // The caret is on the line at fault.
    let caret = browser.run(
        "const e = document.getElementById('config'); \
         return e.value.slice(0, e.selectionStart).split('\\n').length;",
        &[],
    );
    assert_eq!(caret, json!(4));
    // Submit gives the same answer, and no job.
    browser.click(&browser.find("#submit"));
    std::thread::sleep(Duration::from_millis(300));
    let again = shown_text(&browser, "#config-error").expect("still shown");
    assert!(again.starts_with("Line 4, column 9"), "{again}");
    let (_, list) = get(&server, "/api/v1/jobs");
    let list: Value = serde_json::from_slice(&list).expect("JSON");
    assert_eq!(list["jobs"], json!([]));
    browser.screenshot(&shots().join("config-error.png"));
}

#[test]
fn the_jobs_list_updates_without_a_reload() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    if !browser_here() {
        return;
    }
    let dir = scratch("browser-list");
    let server = Server::start(&dir.join("data"), &[]);
    let browser = Browser::start(&dir.join("downloads"), DESKTOP);
    browser.goto(&server.url("/#/jobs"));
    browser.find("#jobs-table");
    // A mark that a reload would wipe.
    browser.run("window.notReloaded = true;", &[]);
    let first = submit(
        &server,
        "pack",
        "[domain]\nshape = \"circle\"\nradius = 15\n[grading]\nuniform = [1.0, 2.0]\n",
        1,
    );
    let second = submit(&server, "pack", gapack::config::DEFAULT_CONFIG, 4);
    for id in [&first, &second] {
        browser.wait("the job listed as succeeded", || {
            let row = browser.run(
                "const r = document.querySelector(`#jobs-table tr[data-id='${arguments[0]}']`); \
                 return r ? r.cells[2].textContent : null;",
                &[json!(id)],
            );
            (row.as_str() == Some("succeeded")).then_some(())
        });
    }
    // Newest first.
    let order = browser.run(
        "return [...document.querySelectorAll('#jobs-table tbody tr')].map(r => r.dataset.id);",
        &[],
    );
    assert_eq!(order, json!([second, first]));
    assert_eq!(
        browser.run("return window.notReloaded === true;", &[]),
        json!(true)
    );
    let words = shown_text(&browser, "#jobs-table tbody").expect("rows");
    assert!(words.contains("porosity 0."), "{words}");
    usable(&browser, "jobs");
    browser.screenshot(&shots().join("jobs.png"));
    browser.window(PHONE.0, PHONE.1);
    std::thread::sleep(Duration::from_millis(300));
    usable(&browser, "jobs at phone width");
}

/// Not a timed test: it checks that a 10⁵-disk packing is drawn whole and
/// follows the pointer, and prints the time to first draw and the frame
/// times while panning, and the page's frame gaps while ten searches stream.
#[test]
fn a_large_packing_and_ten_streaming_jobs_keep_the_page_responsive() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    if !browser_here() {
        return;
    }
    let dir = scratch("browser-large");
    let server = Server::start(&dir.join("data"), &["--workers", "2"]);
    let browser = Browser::start(&dir.join("downloads"), DESKTOP);
    let big = "[domain]\nshape = \"rectangle\"\nwidth = 310\nheight = 310\n\
               [grading]\nuniform = [0.9, 1.1]\n[output]\nformats = [\"csv\", \"png\"]\n";
    let id = submit(&server, "pack", big, 1);
    browser.wait("the big pack", || {
        (state(&server, &id) == "succeeded").then_some(())
    });
    browser.goto(&server.url(&format!("/#/job/{id}")));
    let disks = browser.wait("the packing drawn", || {
        browser
            .run(
                "return window.gapackStats.firstDraw != null ? window.gapackStats.disksDrawn : null;",
                &[],
            )
            .as_u64()
    });
    assert!(
        (80_000..=100_000).contains(&disks),
        "{disks} disks: the scene should hold about 10⁵"
    );
    let drawn = browser.run(
        "return Number(document.getElementById('packing').dataset.drawn);",
        &[],
    );
    assert_eq!(drawn, json!(disks), "every disk drawn at the fitted view");
    let first = browser.run("return window.gapackStats;", &[]);
    browser.run(
        "document.getElementById('packing').scrollIntoView({block: 'start'});",
        &[],
    );
    browser.screenshot(&shots().join("job-large.png"));
    let frames = browser.run(
        "window.gapackStats.frames = []; \
         for (let i = 0; i < 30; i++) window.gapackViewer.panBy(i % 2 ? -25 : 25, 10); \
         return window.gapackStats.frames;",
        &[],
    );
    let mut frames: Vec<f64> = frames
        .as_array()
        .expect("frames")
        .iter()
        .filter_map(Value::as_f64)
        .collect();
    assert_eq!(frames.len(), 30);
    frames.sort_by(f64::total_cmp);
    println!(
        "{disks} disks: fetch and parse {:.0} ms, first draw {:.0} ms after the fetch began; \
         panning: frame p50 {:.1} ms, max {:.1} ms (30 frames)",
        first["fetchParse"].as_f64().unwrap_or(f64::NAN),
        first["firstDraw"].as_f64().unwrap_or(f64::NAN),
        frames[15],
        frames[29]
    );

    // Ten searches streaming at once: the job page of one, then the list.
    let config = "seed = 2\n[domain]\nshape = \"rectangle\"\nwidth = 40\nheight = 40\n\
                  [grading]\nuniform = [1.0, 2.0]\n[optimise]\ntarget_porosity = 0.95\n\
                  population = 6\ngenerations = 400\nstagnation = 10000\n[output]\nformats = [\"csv\"]\n";
    let ids: Vec<String> = (0..10)
        .map(|i| submit(&server, "optimise", config, i))
        .collect();
    browser.goto(&server.url(&format!("/#/job/{}", ids[0])));
    browser.wait("generations streaming", || {
        let n = chart_points(&browser)?;
        (n >= 3).then_some(())
    });
    let gaps = |browser: &Browser| {
        browser.run_async(
            "const done = arguments[arguments.length - 1]; const gaps = []; let last = performance.now(); \
             const end = last + 2000; \
             function step(t) { gaps.push(t - last); last = t; \
               if (t < end) requestAnimationFrame(step); else done(gaps); } \
             requestAnimationFrame(step);",
            &[],
        )
    };
    let report = |what: &str, gaps: Value| {
        let mut g: Vec<f64> = gaps
            .as_array()
            .expect("gaps")
            .iter()
            .filter_map(Value::as_f64)
            .collect();
        assert!(g.len() > 10, "{what}: the page kept drawing frames");
        g.sort_by(f64::total_cmp);
        println!(
            "{what}: {} frames in 2 s, gap p50 {:.1} ms, max {:.1} ms",
            g.len(),
            g[g.len() / 2],
            g[g.len() - 1]
        );
    };
    report("job page, 10 searches streaming", gaps(&browser));
    browser.goto(&server.url("/#/jobs"));
    browser.find("#jobs-table tbody tr");
    report("jobs list, 10 searches streaming", gaps(&browser));
    for id in &ids {
        agent()
            .post(server.url(&format!("/api/v1/jobs/{id}/cancel")))
            .send_empty()
            .expect("cancel");
    }
}

/// A user added to the SQLite store in `data` (before its server
/// starts): their token, the last line `gapack user add` prints.
fn add_user(data: &Path, name: &str) -> String {
    std::fs::create_dir_all(data).expect("data folder");
    let store = format!("sqlite://{}", data.join("gapack.db").display());
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_gapack"))
        .args(["user", "add", name, "--store", &store])
        .output()
        .expect("gapack user add");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8(out.stdout).expect("UTF-8");
    stdout
        .lines()
        .last()
        .expect("a token line")
        .trim()
        .to_owned()
}

#[test]
fn a_signed_in_user_sees_their_name_and_only_their_jobs() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    if !browser_here() {
        return;
    }
    let dir = scratch("browser-users");
    let data = dir.join("data");
    let ana = add_user(&data, "ana");
    let bruno = add_user(&data, "bruno");
    let server = Server::start(&data, &[]);
    let submit_as = |token: &str| {
        let mut r = agent()
            .post(server.url("/api/v1/jobs?kind=pack&seed=1"))
            .header("Content-Type", "application/toml")
            .header("Authorization", &format!("Bearer {token}"))
            .send("[domain]\nshape = \"circle\"\nradius = 10\n[grading]\nuniform = [1.0, 2.0]\n")
            .expect("POST");
        let body: Value =
            serde_json::from_str(&r.body_mut().read_to_string().expect("body")).expect("JSON");
        assert_eq!(r.status().as_u16(), 201, "{body}");
        body["id"].as_str().expect("id").to_owned()
    };
    let anas = submit_as(&ana);
    let brunos = submit_as(&bruno);
    let browser = Browser::start(&dir.join("downloads"), DESKTOP);
    browser.goto(&server.url("/#/jobs"));
    // Users with tokens: the page asks for one.
    browser.wait("the token asked for", || {
        shown_text(&browser, "#token-form label").map(|_| ())
    });
    browser.run(
        "document.getElementById('token').value = arguments[0]; \
         document.getElementById('token-form').requestSubmit();",
        &[json!(bruno)],
    );
    browser.wait("the user named", || {
        shown_text(&browser, "#who-name").filter(|n| n == "bruno")
    });
    browser.wait("bruno's job listed", || {
        let ids = browser.run(
            "return [...document.querySelectorAll('#jobs-table tbody tr')].map(r => r.dataset.id);",
            &[],
        );
        (ids == json!([brunos])).then_some(())
    });
    // Ana's job is no job to bruno, even by its address.
    browser.goto(&server.url(&format!("/#/job/{anas}")));
    browser.wait("a missing job", || {
        shown_text(&browser, "#page-error").filter(|e| e.contains("no job"))
    });
    usable(&browser, "signed in");
}
