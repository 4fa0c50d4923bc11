//! Physical quantities written with their units, as a user writes them in a damper description:
//! `"36 mm"`, `"10 bar"`, `"0.8 mm2"`, `"1e-12 m3/(s.Pa)"`, `"20 degC"`. The unit is a product of
//! prefixed SI symbols with integer powers (`mm2`, `cm3`, `kN.s/m`, `m3/(s.Pa)`), and its
//! dimension is checked against the model parameter's unit in `modelDescription.xml`, which this
//! parser reads the same way.
//!
//! Written here rather than taken from a units crate: the crates that parse unit strings at run
//! time (e.g. `uom` parses none; `dimensioned` and `measurements` neither) do not read the
//! FMI unit syntax (`m3/(s.Pa)`, `N.s/m`) that the checks need on both sides, and the grammar is
//! twenty lines.

use crate::error::Error;
use std::fmt;

/// Exponents of kg, m, s, K, A.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Dimension([i8; 5]);

impl Dimension {
    pub const NONE: Dimension = Dimension([0; 5]);

    fn times(self, other: Dimension, power: i8) -> Dimension {
        Dimension(std::array::from_fn(|i| self.0[i] + power * other.0[i]))
    }
}

impl fmt::Display for Dimension {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let parts: Vec<String> = ["kg", "m", "s", "K", "A"]
            .iter()
            .zip(self.0)
            .filter(|(_, p)| *p != 0)
            .map(|(name, p)| if p == 1 { name.to_string() } else { format!("{name}^{p}") })
            .collect();
        if parts.is_empty() {
            f.write_str("dimensionless")
        } else {
            f.write_str(&parts.join("·"))
        }
    }
}

/// A unit: SI = value·factor + offset, of `dimension`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Unit {
    pub factor: f64,
    pub offset: f64,
    pub dimension: Dimension,
}

const KG: Dimension = Dimension([1, 0, 0, 0, 0]);
const M: Dimension = Dimension([0, 1, 0, 0, 0]);
const S: Dimension = Dimension([0, 0, 1, 0, 0]);
const K: Dimension = Dimension([0, 0, 0, 1, 0]);
const A: Dimension = Dimension([0, 0, 0, 0, 1]);
const NEWTON: Dimension = Dimension([1, 1, -2, 0, 0]);
const PASCAL: Dimension = Dimension([1, -1, -2, 0, 0]);
const VOLUME: Dimension = Dimension([0, 3, 0, 0, 0]);

/// Symbols without a prefix: (symbol, factor to SI, dimension).
const SYMBOLS: [(&str, f64, Dimension); 15] = [
    ("m", 1.0, M),
    ("g", 1e-3, KG),
    ("s", 1.0, S),
    ("min", 60.0, S),
    ("h", 3600.0, S),
    ("K", 1.0, K),
    ("A", 1.0, A),
    ("N", 1.0, NEWTON),
    ("Pa", 1.0, PASCAL),
    ("bar", 1e5, PASCAL),
    ("psi", 6_894.757_293_168_361, PASCAL),
    ("l", 1e-3, VOLUME),
    ("L", 1e-3, VOLUME),
    ("in", 0.0254, M),
    ("rad", 1.0, Dimension::NONE),
];

const PREFIXES: [(&str, f64); 10] = [
    ("G", 1e9),
    ("M", 1e6),
    ("k", 1e3),
    ("da", 10.0),
    ("d", 0.1),
    ("c", 1e-2),
    ("m", 1e-3),
    ("u", 1e-6),
    ("\u{b5}", 1e-6),
    ("\u{3bc}", 1e-6),
];

/// One factor such as `mm2`: a symbol, perhaps prefixed, with an integer power.
fn factor(term: &str) -> Result<(f64, Dimension), Error> {
    let digits = term.trim_start_matches(|c: char| !c.is_ascii_digit() && c != '-');
    let symbol = &term[..term.len() - digits.len()];
    let power: i8 =
        if digits.is_empty() { 1 } else { digits.parse().map_err(|_| Error::BadPower { term: term.to_string() })? };
    if symbol == "1" || (symbol.is_empty() && digits == "1") {
        return Ok((1.0, Dimension::NONE));
    }
    let base = SYMBOLS.iter().find(|(s, _, _)| *s == symbol).map(|&(_, f, d)| (f, d)).or_else(|| {
        PREFIXES.iter().find_map(|(p, pf)| {
            let rest = symbol.strip_prefix(p)?;
            SYMBOLS.iter().find(|(s, _, _)| *s == rest && !["min", "h"].contains(s)).map(|&(_, f, d)| (pf * f, d))
        })
    });
    let (f, d) = base.ok_or_else(|| Error::UnknownUnit { symbol: symbol.to_string() })?;
    Ok((libm::pow(f, power as f64), Dimension::NONE.times(d, power)))
}

/// A product of factors separated by `.`, `*` or `·`.
fn product(text: &str) -> Result<(f64, Dimension), Error> {
    let mut out = (1.0, Dimension::NONE);
    for term in text.split(['.', '*', '\u{b7}']).map(str::trim).filter(|t| !t.is_empty()) {
        let (f, d) = factor(term)?;
        out = (out.0 * f, out.1.times(d, 1));
    }
    Ok(out)
}

/// Parses a unit: `numerator[/denominator]`, the denominator a factor or a parenthesised product;
/// `degC` and `degF` (or `°C`, `°F`) alone; `1`, `-` or nothing for a pure number, `%` for 0.01.
pub fn parse_unit(text: &str) -> Result<Unit, Error> {
    let t = text.trim();
    let affine = |offset: f64, factor: f64| Ok(Unit { factor, offset, dimension: K });
    match t {
        "degC" | "\u{b0}C" => return affine(273.15, 1.0),
        "degF" | "\u{b0}F" => return affine(273.15 - 32.0 * 5.0 / 9.0, 5.0 / 9.0),
        "" | "-" | "1" => return Ok(Unit { factor: 1.0, offset: 0.0, dimension: Dimension::NONE }),
        "%" => return Ok(Unit { factor: 0.01, offset: 0.0, dimension: Dimension::NONE }),
        _ => {}
    }
    let (num, den) = match t.split_once('/') {
        Some((n, d)) => (n, Some(d.trim().trim_start_matches('(').trim_end_matches(')'))),
        None => (t, None),
    };
    let (mut f, mut d) = product(num)?;
    if let Some(den) = den {
        if den.contains('/') {
            return Err(Error::TwoSlashes { unit: t.to_string() });
        }
        let (fd, dd) = product(den)?;
        f /= fd;
        d = d.times(dd, -1);
    }
    Ok(Unit { factor: f, offset: 0.0, dimension: d })
}

/// A value with its unit, `"36 mm"`, in SI with its dimension.
pub fn parse_quantity(text: &str) -> Result<(f64, Dimension), Error> {
    let t = text.trim();
    let split = t
        .char_indices()
        .find(|&(i, c)| {
            // the number ends where a letter starts, unless it is an exponent's e/E followed by a digit or sign
            !(c.is_ascii_digit() || matches!(c, '.' | '+' | '-'))
                && !((c == 'e' || c == 'E')
                    && i > 0
                    && t[i + 1..].starts_with(|n: char| n.is_ascii_digit() || n == '-' || n == '+'))
        })
        .map_or(t.len(), |(i, _)| i);
    let (number, unit) = t.split_at(split);
    let value: f64 = number.trim().parse().map_err(|_| not_a_quantity(t, "does not start with a number"))?;
    if !value.is_finite() {
        return Err(not_a_quantity(t, "is not a finite number"));
    }
    let u = parse_unit(unit)?;
    // a decimal sub-unit divides by its whole reciprocal: 36 mm is 36/1000 = 0.036 m exactly
    // rounded, where 36·1e-3 is 0.036000000000000004
    let per = (1.0 / u.factor).round();
    let si = if u.factor < 1.0 && (per * u.factor - 1.0).abs() < 1e-12 { value / per } else { value * u.factor };
    Ok((si + u.offset, u.dimension))
}

fn not_a_quantity(text: &str, problem: &'static str) -> Error {
    Error::NotAQuantity { text: text.to_string(), problem }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn si(text: &str) -> f64 {
        parse_quantity(text).unwrap().0
    }

    #[test]
    fn values_with_units_are_read_in_si() {
        assert_eq!(si("36 mm"), 0.036);
        assert_eq!(si("10 bar"), 1e6);
        assert!((si("80 cm3") - 80e-6).abs() < 1e-18);
        assert!((si("0.8 mm2") - 0.8e-6).abs() < 1e-18);
        assert_eq!(si("1e-12 m3/(s.Pa)"), 1e-12);
        assert_eq!(si("20 degC"), 293.15);
        assert!((si("68 degF") - 293.15).abs() < 1e-12);
        assert_eq!(si("2.5e7 N/m"), 2.5e7);
        assert_eq!(si("25 kN/mm"), 2.5e7);
        assert_eq!(si("0.035 1/K"), 0.035);
        assert_eq!(si("870 kg/m3"), 870.0);
        assert_eq!(si("5 mm/s"), 0.005);
        assert_eq!(si("3"), 3.0);
        assert_eq!(si("2.5 %"), 0.025);
    }

    #[test]
    fn dimensions_agree_with_the_xml_units() {
        let dim = |u: &str| parse_unit(u).unwrap().dimension;
        assert_eq!(parse_quantity("1e-12 m3/(s.Pa)").unwrap().1, dim("m3/(s.Pa)"));
        assert_eq!(parse_quantity("3 kN.s/m").unwrap().1, dim("N.s/m"));
        assert_eq!(parse_quantity("6e-13 mm2/bar").unwrap().1, dim("m2/Pa"));
        assert_eq!(parse_quantity("5e8 N/m2").unwrap().1, dim("Pa"));
        assert_ne!(dim("m2"), dim("m3"));
        assert_eq!(dim("1/K").to_string(), "K^-1");
    }

    #[test]
    fn bad_units_are_named() {
        assert!(parse_quantity("3 furlongs").unwrap_err().to_string().contains("unknown unit 'furlongs'"));
        assert!(parse_quantity("mm 3").unwrap_err().to_string().contains("does not start with a number"));
        assert!(parse_unit("m/s/s").unwrap_err().to_string().contains("one '/'"));
    }
}
