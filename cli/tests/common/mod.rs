//! Helpers shared by the CLI integration tests (each test file includes
//! this module; not every file uses every helper).
#![allow(dead_code)]

use std::collections::HashMap;
use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Output, Stdio};

/// A bundled test mesh.
pub fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/osd")
        .join(name)
}

/// A scratch directory for output files, inside the target directory.
pub fn out_dir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs `ccss args...` with `stdin` as standard input.
pub fn ccss_stdin(args: &[&str], stdin: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_ccss"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("cannot start ccss");
    // Written from another thread while this one reads the outputs:
    // `ccss eval` answers line by line, so a large input written before
    // reading would block both sides once the output pipe is full. The
    // command may fail before reading all of stdin; ignore EPIPE.
    let mut input = child.stdin.take().unwrap();
    let stdin = stdin.to_owned();
    let writer = std::thread::spawn(move || {
        let _ = input.write_all(stdin.as_bytes());
    });
    let out = child.wait_with_output().unwrap();
    writer.join().unwrap();
    out
}

/// Runs `ccss args...` with no input.
pub fn ccss(args: &[&str]) -> Output {
    ccss_stdin(args, "")
}

pub fn text(b: &[u8]) -> String {
    String::from_utf8(b.to_vec()).unwrap()
}

/// The key=value pairs of a command's one-line summary, checked to be its
/// only output line, with exactly `keys` in that order.
pub fn summary(o: &Output, keys: &[&str]) -> HashMap<String, String> {
    assert!(o.status.success(), "stderr: {}", text(&o.stderr));
    let s = text(&o.stdout);
    let lines: Vec<&str> = s.lines().collect();
    assert_eq!(lines.len(), 1, "{s}");
    let pairs: Vec<(String, String)> = lines[0]
        .split(' ')
        .map(|t| {
            let (k, v) = t.split_once('=').expect(t);
            (k.to_string(), v.to_string())
        })
        .collect();
    let got: Vec<&str> = pairs.iter().map(|(k, _)| k.as_str()).collect();
    assert_eq!(got, keys, "{s}");
    pairs.into_iter().collect()
}

/// A number of a summary.
pub fn num(kv: &HashMap<String, String>, k: &str) -> f64 {
    kv[k]
        .parse()
        .unwrap_or_else(|_| panic!("{k}={} is not a number", kv[k]))
}
