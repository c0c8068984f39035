fn main() {
    std::process::exit(blastsph::cli::main());
}
