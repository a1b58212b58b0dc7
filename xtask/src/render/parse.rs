//! Parsing `cargo xtask render`'s option values: numbers, radius ranges, points, exposure.

use glam::Vec3;

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
}
