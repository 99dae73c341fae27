//! A small W3C WebDriver client for the browser tests: ChromeDriver started
//! on a free loopback port, one headless Chromium session, and the handful
//! of commands the tests use (load a page, find, click, type, run a script,
//! move the pointer, take a screenshot). Plain HTTP and JSON over `ureq`,
//! which the service tests already use: a WebDriver crate would add a TLS
//! stack and an async client for a protocol this small.

use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

/// The key W3C WebDriver names an element reference by.
const ELEMENT: &str = "element-6066-11e4-a52e-4f735466cecf";

/// Where the browser and its driver are: `GAPACK_CHROMIUM` and
/// `GAPACK_CHROMEDRIVER`, or Debian's paths.
fn tool(var: &str, default: &str) -> PathBuf {
    std::env::var_os(var).map_or_else(|| PathBuf::from(default), PathBuf::from)
}

/// Why the browser tests cannot run here, if they cannot.
pub fn missing() -> Option<String> {
    let chromium = tool("GAPACK_CHROMIUM", "/usr/bin/chromium");
    let driver = tool("GAPACK_CHROMEDRIVER", "/usr/bin/chromedriver");
    let absent: Vec<String> = [&chromium, &driver]
        .iter()
        .filter(|p| !p.exists())
        .map(|p| p.display().to_string())
        .collect();
    (!absent.is_empty()).then(|| absent.join(" and "))
}

/// A ChromeDriver process and one browser session, both ended when dropped.
pub struct Browser {
    driver: Child,
    session: String,
    agent: ureq::Agent,
    /// Where downloads go.
    pub downloads: PathBuf,
}

/// An element of the page.
#[derive(Debug, Clone)]
pub struct Element(String);

impl Browser {
    /// Start ChromeDriver and a headless Chromium of `width` × `height`
    /// pixels, downloading into `downloads`.
    ///
    /// # Panics
    /// If either cannot start.
    pub fn start(downloads: &Path, (width, height): (u32, u32)) -> Browser {
        let port = TcpListener::bind("127.0.0.1:0")
            .and_then(|l| l.local_addr())
            .expect("a free port")
            .port();
        let driver = Command::new(tool("GAPACK_CHROMEDRIVER", "/usr/bin/chromedriver"))
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("start chromedriver");
        let agent: ureq::Agent = ureq::Agent::config_builder()
            .http_status_as_error(false)
            .timeout_global(Some(Duration::from_secs(120)))
            .build()
            .into();
        let base = format!("http://127.0.0.1:{port}");
        let start = Instant::now();
        while agent.get(format!("{base}/status")).call().is_err() {
            assert!(
                start.elapsed() < Duration::from_secs(30),
                "chromedriver did not answer"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
        std::fs::create_dir_all(downloads).expect("downloads folder");
        let profile = downloads.with_extension("profile");
        let _ = std::fs::remove_dir_all(&profile);
        let capabilities = json!({"capabilities": {"alwaysMatch": {
            "browserName": "chrome",
            "goog:chromeOptions": {
                "binary": tool("GAPACK_CHROMIUM", "/usr/bin/chromium"),
                "args": [
                    "--headless=new", "--no-sandbox", "--disable-gpu", "--disable-quic",
                    "--no-first-run", "--disable-background-networking",
                    "--disable-component-update", "--disable-sync",
                    "--disable-dev-shm-usage", "--hide-scrollbars",
                    format!("--user-data-dir={}", profile.display()),
                    format!("--window-size={width},{height}"),
                ],
                "prefs": {
                    "download.default_directory": downloads,
                    "download.prompt_for_download": false,
                },
            },
        }}});
        let mut answer = agent
            .post(format!("{base}/session"))
            .header("Content-Type", "application/json")
            .send(capabilities.to_string())
            .expect("new session");
        let text = answer.body_mut().read_to_string().expect("session answer");
        let value: Value = serde_json::from_str(&text).expect("session JSON");
        let session = value["value"]["sessionId"]
            .as_str()
            .unwrap_or_else(|| panic!("no session: {value}"))
            .to_owned();
        let browser = Browser {
            driver,
            session: format!("{base}/session/{session}"),
            agent,
            downloads: downloads.to_path_buf(),
        };
        browser.window(width, height);
        browser
    }

    /// One command; its `value`, or the driver's error.
    fn command(&self, method: &str, path: &str, body: &Value) -> Result<Value, String> {
        let url = format!("{}{path}", self.session);
        let answer = match method {
            "GET" => self.agent.get(&url).call(),
            "DELETE" => self.agent.delete(&url).call(),
            _ => self
                .agent
                .post(&url)
                .header("Content-Type", "application/json")
                .send(body.to_string()),
        };
        let mut answer = answer.map_err(|e| e.to_string())?;
        let ok = answer.status().is_success();
        let text = answer
            .body_mut()
            .with_config()
            .limit(64 << 20)
            .read_to_string()
            .map_err(|e| e.to_string())?;
        let value: Value = serde_json::from_str(&text).map_err(|e| e.to_string())?;
        if ok {
            Ok(value["value"].clone())
        } else {
            Err(value["value"].to_string())
        }
    }

    fn post(&self, path: &str, body: Value) -> Value {
        self.command("POST", path, &body)
            .unwrap_or_else(|e| panic!("POST {path}: {e}"))
    }

    /// The window's size (CSS pixels).
    pub fn window(&self, width: u32, height: u32) {
        self.post("/window/rect", json!({"width": width, "height": height}));
    }

    /// Load `url` and wait for the page.
    pub fn goto(&self, url: &str) {
        self.post("/url", json!({ "url": url }));
    }

    /// The first element `css` selects, if any.
    pub fn try_find(&self, css: &str) -> Option<Element> {
        let value = self
            .command(
                "POST",
                "/element",
                &json!({"using": "css selector", "value": css}),
            )
            .ok()?;
        value[ELEMENT].as_str().map(|id| Element(id.to_owned()))
    }

    /// The first element `css` selects, waiting up to 20 s for it.
    pub fn find(&self, css: &str) -> Element {
        self.wait(&format!("element {css}"), || self.try_find(css))
    }

    pub fn click(&self, element: &Element) {
        self.post(&format!("/element/{}/click", element.0), json!({}));
    }

    /// Type `text` into `element` (after its current text).
    pub fn type_text(&self, element: &Element, text: &str) {
        self.post(
            &format!("/element/{}/value", element.0),
            json!({ "text": text }),
        );
    }

    pub fn clear(&self, element: &Element) {
        self.post(&format!("/element/{}/clear", element.0), json!({}));
    }

    /// Run `script` (a function body; `arguments` holds `args`) in the page.
    pub fn run(&self, script: &str, args: &[Value]) -> Value {
        self.post("/execute/sync", json!({"script": script, "args": args}))
    }

    /// Run `script`, which calls `arguments[arguments.length - 1]` with its result.
    pub fn run_async(&self, script: &str, args: &[Value]) -> Value {
        self.post("/execute/async", json!({"script": script, "args": args}))
    }

    /// Move the mouse to (`x`, `y`) of the viewport (CSS pixels).
    pub fn pointer_to(&self, x: f64, y: f64) {
        self.post(
            "/actions",
            json!({"actions": [{
                "type": "pointer", "id": "mouse", "parameters": {"pointerType": "mouse"},
                "actions": [{"type": "pointerMove", "duration": 0, "origin": "viewport",
                             "x": x.round() as i64, "y": y.round() as i64}],
            }]}),
        );
    }

    /// Press and release `key` (a character, or a WebDriver key code).
    pub fn press(&self, key: &str) {
        self.post(
            "/actions",
            json!({"actions": [{
                "type": "key", "id": "keyboard",
                "actions": [{"type": "keyDown", "value": key}, {"type": "keyUp", "value": key}],
            }]}),
        );
    }

    /// Save a screenshot of the viewport as PNG.
    pub fn screenshot(&self, path: &Path) {
        let value = self
            .command("GET", "/screenshot", &json!({}))
            .unwrap_or_else(|e| panic!("screenshot: {e}"));
        let bytes = base64_decode(value.as_str().unwrap_or_default());
        assert!(bytes.starts_with(b"\x89PNG"), "not a PNG");
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).expect("screenshot folder");
        }
        std::fs::write(path, bytes).expect("write screenshot");
    }

    /// Poll `f` until it gives a value, for at most 60 s.
    ///
    /// # Panics
    /// With `what` if it never does.
    pub fn wait<T>(&self, what: &str, mut f: impl FnMut() -> Option<T>) -> T {
        let start = Instant::now();
        loop {
            if let Some(v) = f() {
                return v;
            }
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "waited 60 s for {what}"
            );
            std::thread::sleep(Duration::from_millis(40));
        }
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.command("DELETE", "", &json!({}));
        let _ = self.driver.kill();
        let _ = self.driver.wait();
    }
}

/// Standard base64 (the screenshot's encoding) to bytes.
fn base64_decode(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => Some(c - b'A'),
        b'a'..=b'z' => Some(c - b'a' + 26),
        b'0'..=b'9' => Some(c - b'0' + 52),
        b'+' => Some(62),
        b'/' => Some(63),
        _ => None,
    };
    let mut out = Vec::with_capacity(text.len() * 3 / 4);
    let (mut acc, mut bits) = (0u32, 0u32);
    for c in text.bytes().filter_map(value) {
        acc = (acc << 6) | u32::from(c);
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
        }
    }
    out
}
