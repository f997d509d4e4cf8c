//! Value parsers for command-line flags: clap names the flag in every refusal, so a bad
//! value is reported where it was typed, not later as a failure of something else.

/// A number that is not NaN (infinite values are allowed: an uncapped friction is `inf`).
pub fn not_nan(s: &str) -> Result<f64, String> {
    let x: f64 = s.trim().parse().map_err(|_| format!("`{s}` is not a number"))?;
    if x.is_nan() {
        return Err("must be a number, not NaN".into());
    }
    Ok(x)
}

/// A finite number greater than zero.
pub fn positive(s: &str) -> Result<f64, String> {
    let x = not_nan(s)?;
    if !(x.is_finite() && x > 0.0) {
        return Err(format!("must be a positive finite number, got {x}"));
    }
    Ok(x)
}

/// A finite number of at least zero.
pub fn non_negative(s: &str) -> Result<f64, String> {
    let x = not_nan(s)?;
    if !(x.is_finite() && x >= 0.0) {
        return Err(format!("must be a finite number >= 0, got {x}"));
    }
    Ok(x)
}

/// A window `FROM,TO` of seconds, `FROM <= TO`.
pub fn window(s: &str) -> Result<(f64, f64), String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("expected FROM,TO in seconds, got `{s}`"))?;
    match v[..] {
        [a, b] if a <= b => Ok((a, b)),
        _ => Err(format!("expected FROM,TO with FROM <= TO, got `{s}`")),
    }
}

/// A reference point `T:S`: a positive time in seconds and a count of at least zero.
pub fn time_count(s: &str) -> Result<(f64, f64), String> {
    let bad = || format!("expected T:S, a time in seconds above 0 and a count of at least 0 (e.g. 100:9), got `{s}`");
    let (t, c) = s.split_once(':').ok_or_else(bad)?;
    match (t.trim().parse::<f64>(), c.trim().parse::<f64>()) {
        (Ok(t), Ok(c)) if t > 0.0 && t.is_finite() && c >= 0.0 && c.is_finite() => Ok((t, c)),
        _ => Err(bad()),
    }
}

/// A count of at least one.
pub fn at_least_one(s: &str) -> Result<usize, String> {
    at_least(s, 1)
}

/// A count of at least two (a sweep needs two ends).
pub fn at_least_two(s: &str) -> Result<usize, String> {
    at_least(s, 2)
}

fn at_least(s: &str, min: usize) -> Result<usize, String> {
    let n: usize = s.trim().parse().map_err(|_| format!("`{s}` is not a whole number"))?;
    if n < min {
        return Err(format!("must be at least {min}, got {n}"));
    }
    Ok(n)
}

/// A parser of one law-slot kind by its scene-file names (the same type the scene uses).
pub fn kind<K: std::str::FromStr<Err = particles::error::UnknownName> + Clone + Send + Sync + 'static>(
    names: &'static [&'static str],
) -> impl clap::builder::TypedValueParser<Value = K> {
    use clap::builder::TypedValueParser as _;
    clap::builder::PossibleValuesParser::new(names).map(|s| s.parse::<K>().expect("one of the names"))
}

/// Parses "x,y,z" into a vector.
pub fn parse_vec3(s: &str) -> Result<[f64; 3], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!("expected three comma-separated numbers like 0,0,10, got `{s}`"));
    }
    let mut v = [0.0; 3];
    for (k, p) in parts.iter().enumerate() {
        v[k] = p.parse().map_err(|_| format!("`{p}` is not a number"))?;
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parsers_refuse_nan_non_positive_and_small_counts() {
        assert!(not_nan("nan").is_err());
        assert_eq!(not_nan("inf"), Ok(f64::INFINITY));
        assert_eq!(not_nan("-2.5"), Ok(-2.5));
        assert!(positive("0").is_err() && positive("-1e-3").is_err() && positive("inf").is_err());
        assert_eq!(positive("1e-3"), Ok(1e-3));
        assert!(at_least_one("0").is_err());
        assert_eq!(at_least_one("3"), Ok(3));
        assert!(at_least_two("1").is_err());
        assert!(at_least_two("x").is_err());
    }
}
