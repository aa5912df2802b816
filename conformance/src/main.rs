//! `conformance report --out DIR`: the rendered-quality study as an HTML page.
fn main() {
    eprintln!("conformance: no command yet");
}
