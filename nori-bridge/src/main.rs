//! nori-bridge: the software side of rtaccel (issue 7 builds it out).
fn main() {
    eprintln!("Error: nori-bridge has no commands yet (issue 7)");
    std::process::exit(1);
}
