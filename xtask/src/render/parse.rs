//! Parsing `cargo xtask render`'s option values: numbers, radius ranges, points, exposure,
//! ambient light.

use glam::Vec3;
use renderer::frame::Ambient;

/// Comma-separated finite numbers, exactly `N` of them.
fn parse_numbers<const N: usize>(s: &str, what: &str) -> Result<[f32; N], String> {
    let values: Vec<f32> = s
        .split(',')
        .map(|v| v.trim().parse::<f32>().ok().filter(|v| v.is_finite()))
        .collect::<Option<_>>()
        .ok_or_else(|| format!("{s:?} is not {what}"))?;
    values
        .try_into()
        .map_err(|_| format!("{s:?} is not {what}"))
}

/// `MIN,MAX` with `0 < MIN <= MAX`.
pub(super) fn parse_radius_range(s: &str) -> Result<(f32, f32), String> {
    let [min, max] = parse_numbers::<2>(s, "MIN,MAX (two numbers, e.g. 0.5,3)")?;
    if min > 0.0 && min <= max {
        Ok((min, max))
    } else {
        Err(format!("{s:?}: give MIN,MAX with 0 < MIN <= MAX"))
    }
}

/// An exposure in stops, within ±16.
pub(crate) fn parse_exposure(s: &str) -> Result<f32, String> {
    let [ev] = parse_numbers::<1>(s, "a number of stops (e.g. 0.5 or -1)")?;
    if ev.abs() <= 16.0 {
        Ok(ev)
    } else {
        Err(format!("{s:?}: give an exposure between -16 and 16 stops"))
    }
}

/// `X,Y,Z`.
pub(super) fn parse_vec3(s: &str) -> Result<Vec3, String> {
    parse_numbers::<3>(s, "X,Y,Z (three numbers, e.g. 0,2,5)").map(Vec3::from_array)
}

/// `off`, one `R,G,B` (sky and ground alike) or `SKY:GROUND` (each `R,G,B`): linear radiance,
/// finite and not negative.
pub(super) fn parse_ambient(s: &str) -> Result<Ambient, String> {
    let what = "off, R,G,B or SKY_R,G,B:GROUND_R,G,B (e.g. 0.3,0.3,0.3:0.1,0.1,0.1)";
    if s.trim() == "off" {
        return Ok(Ambient::OFF);
    }
    let colour = |c: &str| {
        let v = parse_numbers::<3>(c, what).map(Vec3::from_array)?;
        if v.min_element() >= 0.0 {
            Ok(v)
        } else {
            Err(format!("{s:?}: ambient radiance cannot be negative"))
        }
    };
    match s.split_once(':') {
        Some((sky, ground)) => Ok(Ambient {
            sky: colour(sky)?,
            ground: colour(ground)?,
        }),
        None => colour(s).map(Ambient::uniform),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radius_ranges_and_points_parse_as_documented() {
        assert_eq!(parse_radius_range("50,200"), Ok((50.0, 200.0)));
        assert_eq!(parse_radius_range(" 0.5 , 3 "), Ok((0.5, 3.0)));
        for bad in ["50", "50,200,300", "0,1", "2,1", "a,b", "1,inf", ""] {
            assert!(parse_radius_range(bad).is_err(), "{bad:?} must be refused");
        }
        assert_eq!(parse_vec3("0,2,-5"), Ok(Vec3::new(0.0, 2.0, -5.0)));
        assert!(parse_vec3("1,2").is_err());
        assert!(parse_vec3("1,2,NaN").is_err());
    }

    #[test]
    fn ambient_parses_as_documented() {
        assert_eq!(parse_ambient("off"), Ok(Ambient::OFF));
        assert_eq!(
            parse_ambient("0.5,0.25,0"),
            Ok(Ambient {
                sky: Vec3::new(0.5, 0.25, 0.0),
                ground: Vec3::new(0.5, 0.25, 0.0),
            })
        );
        assert_eq!(
            parse_ambient("0.3,0.2,0.1:0.01,0.02,0.03"),
            Ok(Ambient {
                sky: Vec3::new(0.3, 0.2, 0.1),
                ground: Vec3::new(0.01, 0.02, 0.03),
            })
        );
        for bad in [
            "",
            "0.3",
            "1,2,3:",
            ":1,2,3",
            "1,2,3:4,5",
            "-1,0,0",
            "0,0,0:0,-0.1,0",
            "on",
        ] {
            assert!(parse_ambient(bad).is_err(), "{bad:?} must be refused");
        }
    }
}
