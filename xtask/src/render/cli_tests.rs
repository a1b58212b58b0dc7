//! `cargo xtask render`'s options as clap parses them from a command line: vector options
//! take negative numbers after a space, and the ambient option reaches `Args`.

use glam::Vec3;
use renderer::frame::Ambient;

/// The options as the `render` subcommand receives them.
#[derive(Debug, clap::Parser)]
struct Cli {
    #[command(flatten)]
    args: super::Args,
}

fn parse_cli(line: &[&str]) -> Result<super::Args, clap::Error> {
    use clap::Parser as _;
    Cli::try_parse_from(std::iter::once("render").chain(line.iter().copied())).map(|c| c.args)
}

#[test]
fn the_ambient_option_reaches_the_arguments() {
    let args =
        parse_cli(&["--ambient", "0.4,0.4,0.4:0,0,0.1"]).unwrap_or_else(|e| panic!("refused: {e}"));
    assert_eq!(
        args.ambient,
        Some(Ambient {
            sky: Vec3::splat(0.4),
            ground: Vec3::new(0.0, 0.0, 0.1),
        })
    );
}

#[test]
fn vector_options_take_negative_numbers_after_a_space() {
    let args = parse_cli(&["--eye", "-18,0,0", "--target", "-0.5,-1,2"])
        .unwrap_or_else(|e| panic!("refused: {e}"));
    assert_eq!(args.eye, Some(Vec3::new(-18.0, 0.0, 0.0)));
    assert_eq!(args.target, Some(Vec3::new(-0.5, -1.0, 2.0)));
    let args = parse_cli(&["--eye=-1,2,3", "--target", "0,0,0", "--exposure", "-1.5"])
        .unwrap_or_else(|e| panic!("refused: {e}"));
    assert_eq!(args.eye, Some(Vec3::new(-1.0, 2.0, 3.0)));
    assert_eq!(args.exposure, Some(-1.5));
    // A flag where a value belongs is still refused (by the value parser), not swallowed.
    assert!(parse_cli(&["--eye", "--target", "1,2,3"]).is_err());
    assert!(parse_cli(&["--eye", "-18,0", "--target", "0,0,0"]).is_err());
}
