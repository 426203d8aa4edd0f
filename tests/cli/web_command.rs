//! `qjulia web`: serves a built page on 127.0.0.1 (a port of its own with `--port 0`, printed),
//! files inside the folder only; without a built page it says how to build one, on one line,
//! and exits 1.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Command, Stdio};

/// A GET of `path`: the status code and the body.
fn get(addr: &str, path: &str) -> (u16, String) {
    let mut stream = TcpStream::connect(addr).unwrap();
    write!(
        stream,
        "GET {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut text = String::new();
    stream.read_to_string(&mut text).unwrap();
    let status = text.split(' ').nth(1).unwrap().parse().unwrap();
    let body = text
        .split_once("\r\n\r\n")
        .map_or("", |(_, b)| b)
        .to_string();
    (status, body)
}

#[test]
fn serves_the_built_page_on_localhost() {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("dist");
    std::fs::create_dir_all(page.join("assets")).unwrap();
    std::fs::write(page.join("index.html"), "<title>qjulia</title>").unwrap();
    std::fs::write(page.join("assets/main.js"), "console.log(1)").unwrap();
    std::fs::write(dir.path().join("secret.txt"), "outside").unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_qjulia"))
        .args(["web", "--port", "0", "--dir"])
        .arg(&page)
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let addr = line
        .split("http://")
        .nth(1)
        .and_then(|rest| rest.split('/').next())
        .unwrap_or_else(|| panic!("no address in {line:?}"))
        .to_string();
    assert!(addr.starts_with("127.0.0.1:"), "{line}");
    let outcome = std::panic::catch_unwind(|| {
        assert_eq!(get(&addr, "/"), (200, "<title>qjulia</title>".into()));
        assert_eq!(get(&addr, "/assets/main.js").0, 200);
        assert_eq!(get(&addr, "/missing.js").0, 404);
        assert_eq!(get(&addr, "/../secret.txt").0, 404);
        assert_eq!(get(&addr, "/%2e%2e/secret.txt").0, 404);
    });
    child.kill().unwrap();
    child.wait().unwrap();
    outcome.unwrap();
}

#[test]
fn without_a_built_page_it_says_how_to_build_one() {
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_qjulia"))
        .args(["web", "--port", "0", "--dir"])
        .arg(dir.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains(
            "has no index.html: build the page first (cd web && npm ci && npm run build)"
        ),
        "{stderr}"
    );
}
