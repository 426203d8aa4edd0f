//! `qjulia web`: the browser page (web/dist, built by `npm run build` in web/) served on
//! localhost from the binary, so that a native user opens it in one command. Static files only,
//! GET and HEAD, nothing outside the folder; bound to 127.0.0.1 unless asked otherwise.

use std::io;
use std::net::SocketAddr;
use std::path::{Component, Path, PathBuf};

/// The built page beside the sources this binary was built from.
pub fn default_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("web")
        .join("dist")
}

/// What `qjulia web` says where the page has not been built.
pub fn not_built(dir: &Path) -> String {
    format!(
        "{} has no index.html: build the page first (cd web && npm ci && npm run build), or name \
         a built page with --dir",
        dir.display()
    )
}

/// The file under `dir` that a request's path names, or None where the path leaves the folder
/// or names nothing there. `/` and folders give their index.html.
pub fn resolve(dir: &Path, url: &str) -> Option<PathBuf> {
    let path = url.split(['?', '#']).next().unwrap_or("");
    let decoded = percent_decode(path)?;
    let mut file = dir.to_path_buf();
    for part in Path::new(decoded.trim_start_matches('/')).components() {
        match part {
            Component::Normal(p) => file.push(p),
            Component::CurDir => {}
            _ => return None,
        }
    }
    if file.is_dir() {
        file.push("index.html");
    }
    file.is_file().then_some(file)
}

/// `%XX` escapes decoded; None where one is broken or the result is not UTF-8.
fn percent_decode(s: &str) -> Option<String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut k = 0;
    while k < bytes.len() {
        if bytes[k] == b'%' {
            let hex = std::str::from_utf8(bytes.get(k + 1..k + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            k += 3;
        } else {
            out.push(bytes[k]);
            k += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// The media type of a file the page has.
pub fn content_type(file: &Path) -> &'static str {
    match file.extension().and_then(|e| e.to_str()) {
        Some("html") => "text/html; charset=utf-8",
        Some("js") => "text/javascript; charset=utf-8",
        Some("css") => "text/css; charset=utf-8",
        Some("json") => "application/json",
        Some("png") => "image/png",
        Some("svg") => "image/svg+xml",
        Some("wasm") => "application/wasm",
        Some("toml") | Some("txt") => "text/plain; charset=utf-8",
        _ => "application/octet-stream",
    }
}

/// A server of `dir` on `addr` (port 0: any free one).
pub struct PageServer {
    server: tiny_http::Server,
    dir: PathBuf,
}

impl PageServer {
    /// Binds `addr`; the one line why not where `dir` has no built page or the address is
    /// taken.
    pub fn bind(dir: &Path, addr: SocketAddr) -> Result<Self, String> {
        if !dir.join("index.html").is_file() {
            return Err(not_built(dir));
        }
        let server =
            tiny_http::Server::http(addr).map_err(|e| format!("cannot listen on {addr}: {e}"))?;
        Ok(Self {
            server,
            dir: dir.to_path_buf(),
        })
    }

    /// The address it listens on.
    pub fn addr(&self) -> SocketAddr {
        self.server
            .server_addr()
            .to_ip()
            .expect("an HTTP server on an IP address")
    }

    /// Answers requests until the process ends.
    pub fn run(&self) {
        for request in self.server.incoming_requests() {
            let _ = self.answer(request);
        }
    }

    fn answer(&self, request: tiny_http::Request) -> io::Result<()> {
        use tiny_http::{Header, Method, Response};
        if !matches!(request.method(), Method::Get | Method::Head) {
            return request.respond(Response::empty(405));
        }
        let Some(file) = resolve(&self.dir, request.url()) else {
            return request.respond(Response::from_string("not found").with_status_code(404));
        };
        let body = std::fs::File::open(&file)?;
        let header = Header::from_bytes("Content-Type", content_type(&file)).expect("ASCII");
        let cache = Header::from_bytes("Cache-Control", "no-cache").expect("ASCII");
        request.respond(
            Response::from_file(body)
                .with_header(header)
                .with_header(cache),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolves_inside_the_folder_only() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::write(d.join("index.html"), "<p>").unwrap();
        std::fs::create_dir(d.join("assets")).unwrap();
        std::fs::write(d.join("assets/a b.js"), "x").unwrap();
        assert_eq!(resolve(d, "/"), Some(d.join("index.html")));
        assert_eq!(resolve(d, "/?x=1#frag"), Some(d.join("index.html")));
        assert_eq!(
            resolve(d, "/assets/a%20b.js"),
            Some(d.join("assets/a b.js"))
        );
        assert_eq!(resolve(d, "/missing.js"), None);
        assert_eq!(resolve(d, "/../index.html"), None);
        assert_eq!(resolve(d, "/assets/%2e%2e/%2e%2e/etc/passwd"), None);
        assert_eq!(resolve(d, "/%zz"), None);
    }
}
