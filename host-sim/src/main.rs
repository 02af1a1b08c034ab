//! `deploywatch`: the command line.
fn main() {
    println!("deploywatch");
}
