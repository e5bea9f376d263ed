//! Prints `brume info` for a VDB file: `cargo run --release --example vdb_info -- FILE [--json]`.

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: vdb_info FILE.vdb [--json]");
        std::process::exit(2);
    };
    let json = args.iter().any(|a| a == "--json");
    match brume::volume::info_report(std::path::Path::new(path), json) {
        Ok(text) => print!("{text}"),
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    }
}
