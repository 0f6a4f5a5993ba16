fn main() {
    if let Err(e) = nori_bridge::cli::run() {
        eprintln!("Error: {e:#}");
        std::process::exit(1);
    }
}
