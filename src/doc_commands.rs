//! The guide cannot drift from the command line (issue 28, point 6): every `sward …` and
//! `cargo run --release -- …` command in the code blocks of the README and of `docs/*.md`
//! is parsed by the binary's own parser ([`super::Cli`], with its ranges and value
//! parsers), and every relative link and picture in those pages names a file that exists.

use std::path::{Path, PathBuf};

use clap::Parser;

/// The README and every page of the guide.
fn pages() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut pages = vec![root.join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .expect("docs/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    pages.extend(docs);
    pages
}

/// `line` split into words as a shell would: whitespace outside quotes, `'…'` and `"…"`
/// kept whole without their quotes; a `#` starting a word ends the line (a comment).
fn words(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut word = String::new();
    let mut in_word = false;
    let mut quote = None;
    for c in line.chars() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), c) => word.push(c),
            (None, '\'' | '"') => {
                quote = Some(c);
                in_word = true;
            }
            (None, '#') if !in_word => break,
            (None, c) if c.is_whitespace() => {
                if in_word {
                    out.push(std::mem::take(&mut word));
                    in_word = false;
                }
            }
            (None, c) => {
                word.push(c);
                in_word = true;
            }
        }
    }
    if in_word {
        out.push(word);
    }
    out
}

/// The `sward` arguments of a command line, or `None` when it runs something else (the
/// library's example, cargo test, apt-get): `sward ARGS`, `cargo run --release -- ARGS`
/// and `cargo run --release`, after any `NAME=value` environment words.
fn sward_args(words: &[String]) -> Option<Vec<String>> {
    let start = words
        .iter()
        .position(|w| !w.contains('=') || w.starts_with('-'))?;
    let words = &words[start..];
    let program = |rest: &[String]| {
        let mut args = vec!["sward".to_string()];
        args.extend(rest.iter().cloned());
        args
    };
    match words.first()?.as_str() {
        "sward" => Some(program(&words[1..])),
        "cargo" if words.get(1).is_some_and(|w| w == "run") => {
            if words.iter().any(|w| w == "-p" || w == "--example") {
                return None;
            }
            match words.iter().position(|w| w == "--") {
                Some(dash) => Some(program(&words[dash + 1..])),
                None => Some(program(&[])),
            }
        }
        _ => None,
    }
}

/// The commands in `text`'s fenced code blocks, with their line numbers; a line ending in
/// `\` continues on the next. Then those in inline code spans (the pictures' captions
/// give the command that made them) with at least one option, but those that show a
/// placeholder (`…`, `[`, or a capital standing for a value, as in `--out docs/S.png`).
fn commands(text: &str) -> Vec<(usize, Vec<String>)> {
    let mut out = blocks(text);
    out.extend(inline(text));
    out
}

/// Inline code spans that hold a whole command, joined across the lines of a paragraph.
fn inline(text: &str) -> Vec<(usize, Vec<String>)> {
    let mut out = Vec::new();
    let mut in_block = false;
    let mut paragraph: Vec<(usize, &str)> = Vec::new();
    let flush = |paragraph: &mut Vec<(usize, &str)>, out: &mut Vec<(usize, Vec<String>)>| {
        let joined: String = paragraph
            .iter()
            .map(|(_, l)| *l)
            .collect::<Vec<_>>()
            .join(" ");
        let first = paragraph.first().map_or(0, |(i, _)| *i);
        for (k, span) in joined.split('`').enumerate() {
            let placeholder = span.contains('…')
                || span.contains('[')
                || span
                    .split(|c: char| !c.is_alphanumeric())
                    .any(|w| w.len() == 1 && w.chars().all(|c| c.is_ascii_uppercase()));
            if k % 2 == 1 && !placeholder {
                if let Some(args) = sward_args(&words(span)) {
                    if args.iter().any(|a| a.starts_with("--")) {
                        out.push((first, args));
                    }
                }
            }
        }
        paragraph.clear();
    };
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            in_block = !in_block;
            flush(&mut paragraph, &mut out);
            continue;
        }
        if in_block {
            continue;
        }
        if line.trim().is_empty() {
            flush(&mut paragraph, &mut out);
        } else {
            paragraph.push((i + 1, line));
        }
    }
    flush(&mut paragraph, &mut out);
    out
}

/// The commands of the fenced code blocks.
fn blocks(text: &str) -> Vec<(usize, Vec<String>)> {
    let mut out = Vec::new();
    let mut in_block = false;
    let mut pending: Option<(usize, String)> = None;
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            in_block = !in_block;
            continue;
        }
        if !in_block {
            continue;
        }
        let (at, mut joined) = pending.take().unwrap_or((i + 1, String::new()));
        joined.push_str(line.trim());
        if let Some(stripped) = joined.strip_suffix('\\') {
            pending = Some((at, stripped.to_string() + " "));
            continue;
        }
        if let Some(args) = sward_args(&words(&joined)) {
            out.push((at, args));
        }
    }
    out
}

#[test]
fn shell_words_and_program_arguments() {
    assert_eq!(
        words("sward render --set 'a=(1.0, 2)' --out x.png   # a comment"),
        ["sward", "render", "--set", "a=(1.0, 2)", "--out", "x.png"]
    );
    let args = |s: &str| sward_args(&words(s));
    assert_eq!(
        args("RUST_LOG=sward=info cargo run --release -- --size 1280x720").unwrap(),
        ["sward", "--size", "1280x720"]
    );
    assert_eq!(args("cargo run --release").unwrap(), ["sward"]);
    assert_eq!(args("cargo run --release -p sward --example embed"), None);
    assert_eq!(args("cargo test --release"), None);
    let found = commands("text\n```sh\nsward render \\\n  --frames 3\n```\nsward --bogus\n");
    assert_eq!(
        found,
        [(
            3,
            vec![
                "sward".into(),
                "render".into(),
                "--frames".into(),
                "3".into()
            ]
        )]
    );
}

#[test]
fn every_command_in_the_guide_parses() {
    let mut checked = 0;
    let mut failures = Vec::new();
    for page in pages() {
        let text = std::fs::read_to_string(&page).expect("page");
        for (line, args) in commands(&text) {
            checked += 1;
            if let Err(e) = super::Cli::try_parse_from(&args) {
                if e.kind() != clap::error::ErrorKind::DisplayHelp
                    && e.kind() != clap::error::ErrorKind::DisplayVersion
                {
                    let first = e.to_string().lines().next().unwrap_or("").to_string();
                    failures.push(format!(
                        "{}:{line}: {}: {first}",
                        page.display(),
                        args.join(" ")
                    ));
                }
            }
        }
    }
    assert!(checked >= 50, "only {checked} commands found in the guide");
    println!("{checked} commands parsed");
    assert!(
        failures.is_empty(),
        "commands that do not parse:\n{}",
        failures.join("\n")
    );
}

#[test]
fn every_relative_link_in_the_guide_exists() {
    let mut missing = Vec::new();
    let mut checked = 0;
    for page in pages() {
        let text = std::fs::read_to_string(&page).expect("page");
        let dir = page.parent().expect("a directory");
        for (i, line) in text.lines().enumerate() {
            let mut rest = line;
            while let Some(at) = rest.find("](") {
                let tail = &rest[at + 2..];
                let Some(end) = tail.find(')') else { break };
                let target = &tail[..end];
                rest = &tail[end..];
                if target.contains("://")
                    || target.starts_with('#')
                    || target.starts_with("mailto:")
                {
                    continue;
                }
                let path = target.split('#').next().unwrap_or(target);
                checked += 1;
                if !dir.join(path).exists() {
                    missing.push(format!("{}:{}: {target}", page.display(), i + 1));
                }
            }
        }
    }
    assert!(checked >= 30, "only {checked} links found");
    assert!(
        missing.is_empty(),
        "links to nothing:\n{}",
        missing.join("\n")
    );
}
