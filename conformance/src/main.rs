fn main() {
    eprintln!("conformance: no command yet");
}
