//! Measurement columns (named like the FMU's variables) and the units a column may be given in.

use std::fmt;

/// What a unit measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    Time,
    Length,
    Velocity,
    Force,
    Pressure,
    Current,
    Temperature,
}

impl fmt::Display for Quantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Quantity::Time => "a time",
            Quantity::Length => "a length",
            Quantity::Velocity => "a velocity",
            Quantity::Force => "a force",
            Quantity::Pressure => "a pressure",
            Quantity::Current => "a current",
            Quantity::Temperature => "a temperature",
        })
    }
}

/// Units accepted in a header (`F_damper [kN]`) or a `--map`, with their factor to SI. The inch,
/// pound-force and psi are the exact international definitions (1 in = 25.4 mm,
/// 1 lbf = 0.45359237 kg · 9.80665 m/s²); µ may be written as the micro sign, the Greek mu or `u`.
pub const UNITS: [(&str, Quantity, f64); 33] = [
    ("s", Quantity::Time, 1.0),
    ("ms", Quantity::Time, 1e-3),
    ("us", Quantity::Time, 1e-6),
    ("\u{b5}s", Quantity::Time, 1e-6),
    ("\u{3bc}s", Quantity::Time, 1e-6),
    ("m", Quantity::Length, 1.0),
    ("cm", Quantity::Length, 1e-2),
    ("mm", Quantity::Length, 1e-3),
    ("um", Quantity::Length, 1e-6),
    ("\u{b5}m", Quantity::Length, 1e-6),
    ("\u{3bc}m", Quantity::Length, 1e-6),
    ("in", Quantity::Length, 0.0254),
    ("m/s", Quantity::Velocity, 1.0),
    ("cm/s", Quantity::Velocity, 1e-2),
    ("mm/s", Quantity::Velocity, 1e-3),
    ("in/s", Quantity::Velocity, 0.0254),
    ("N", Quantity::Force, 1.0),
    ("daN", Quantity::Force, 10.0),
    ("kN", Quantity::Force, 1e3),
    ("lbf", Quantity::Force, 0.45359237 * 9.80665),
    ("Pa", Quantity::Pressure, 1.0),
    ("kPa", Quantity::Pressure, 1e3),
    ("MPa", Quantity::Pressure, 1e6),
    ("mbar", Quantity::Pressure, 1e2),
    ("bar", Quantity::Pressure, 1e5),
    ("psi", Quantity::Pressure, 0.45359237 * 9.80665 / (0.0254 * 0.0254)),
    ("A", Quantity::Current, 1.0),
    ("mA", Quantity::Current, 1e-3),
    ("K", Quantity::Temperature, 1.0),
    ("degC", Quantity::Temperature, 1.0),
    ("\u{b0}C", Quantity::Temperature, 1.0),
    ("degF", Quantity::Temperature, 5.0 / 9.0),
    ("\u{b0}F", Quantity::Temperature, 5.0 / 9.0),
];

/// The SI offset of a unit whose zero is not SI's (temperatures): SI = value·factor + offset.
/// 0 °C = 273.15 K; 0 °F = (0 − 32)·5/9 °C = 255.372… K.
pub fn unit_offset(unit: &str) -> f64 {
    match unit.trim().to_ascii_lowercase().as_str() {
        "degc" | "\u{b0}c" => 273.15,
        "degf" | "\u{b0}f" => 273.15 - 32.0 * 5.0 / 9.0,
        _ => 0.0,
    }
}

/// The quantity and SI factor of `unit`: the exact spelling, or one that differs only in the case
/// of letters other than `m`/`M` (`KN`, `BAR`, `Mpa` are read; `MM`, `mPa`, `MA` are not: m is milli
/// and M mega, so their case carries a factor of 10⁹ and a guess could be that wrong).
pub fn unit(unit: &str) -> Option<(Quantity, f64)> {
    let u = unit.trim();
    let loose = |name: &str| {
        name.len() == u.len()
            && name.chars().zip(u.chars()).all(|(a, b)| a == b || (a.eq_ignore_ascii_case(&b) && a != 'm' && a != 'M'))
    };
    UNITS
        .iter()
        .find(|(name, _, _)| *name == u)
        .or_else(|| UNITS.iter().find(|(name, _, _)| loose(name)))
        .map(|&(_, q, f)| (q, f))
}

/// The list of accepted units, for error messages.
pub fn unit_list() -> String {
    UNITS.iter().map(|(n, _, _)| *n).collect::<Vec<_>>().join(", ")
}

/// A measurement column the tool understands.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Column {
    Time,
    VDamper,
    XDamper,
    FDemand,
    XSpoolDemand,
    FDamper,
    XSpool,
    ISol,
    PExt,
    PComp,
    TOil,
}

impl Column {
    pub const ALL: [Column; 11] = [
        Column::Time,
        Column::VDamper,
        Column::XDamper,
        Column::FDemand,
        Column::XSpoolDemand,
        Column::FDamper,
        Column::XSpool,
        Column::ISol,
        Column::PExt,
        Column::PComp,
        Column::TOil,
    ];

    /// The name, as the FMU's variable.
    pub fn name(self) -> &'static str {
        match self {
            Column::Time => "time",
            Column::VDamper => "v_damper",
            Column::XDamper => "x_damper",
            Column::FDemand => "F_demand",
            Column::XSpoolDemand => "x_spool_demand",
            Column::FDamper => "F_damper",
            Column::XSpool => "x_spool",
            Column::ISol => "i_sol",
            Column::PExt => "p_ext",
            Column::PComp => "p_comp",
            Column::TOil => "T_oil",
        }
    }

    pub fn from_name(name: &str) -> Option<Column> {
        Column::ALL.into_iter().find(|c| c.name() == name)
    }

    pub fn quantity(self) -> Quantity {
        match self {
            Column::Time => Quantity::Time,
            Column::VDamper => Quantity::Velocity,
            Column::XDamper | Column::XSpoolDemand | Column::XSpool => Quantity::Length,
            Column::FDemand | Column::FDamper => Quantity::Force,
            Column::ISol => Quantity::Current,
            Column::PExt | Column::PComp => Quantity::Pressure,
            Column::TOil => Quantity::Temperature,
        }
    }

    /// SI unit.
    pub fn si_unit(self) -> &'static str {
        match self.quantity() {
            Quantity::Time => "s",
            Quantity::Length => "m",
            Quantity::Velocity => "m/s",
            Quantity::Force => "N",
            Quantity::Pressure => "Pa",
            Quantity::Current => "A",
            Quantity::Temperature => "K",
        }
    }

    /// Unit used in plots and tables (readable magnitudes) and its factor from SI.
    pub fn display_unit(self) -> (&'static str, f64) {
        match self {
            Column::Time => ("s", 1.0),
            Column::VDamper => ("m/s", 1.0),
            Column::XDamper | Column::XSpoolDemand | Column::XSpool => ("mm", 1e3),
            Column::FDemand | Column::FDamper => ("kN", 1e-3),
            Column::ISol => ("A", 1.0),
            Column::PExt | Column::PComp => ("bar", 1e-5),
            Column::TOil => ("K", 1.0),
        }
    }

    /// One line of meaning, for errors and the report.
    pub fn meaning(self) -> &'static str {
        match self {
            Column::Time => "sample time",
            Column::VDamper => "damper velocity, extension +",
            Column::XDamper => "damper displacement, extension +",
            Column::FDemand => "force demand, tension +",
            Column::XSpoolDemand => "spool position demand",
            Column::FDamper => "measured (load-cell) force, tension +",
            Column::XSpool => "spool position",
            Column::ISol => "solenoid current",
            Column::PExt => "extension (annulus) chamber gauge pressure",
            Column::PComp => "compression (full-bore) chamber gauge pressure",
            Column::TOil => "oil temperature (an input of the model when effect oil_temperature is on)",
        }
    }
}

impl fmt::Display for Column {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_resolve() {
        assert_eq!(unit("kN"), Some((Quantity::Force, 1e3)));
        assert_eq!(unit("kn"), Some((Quantity::Force, 1e3)));
        assert_eq!(unit("cm/s"), Some((Quantity::Velocity, 1e-2)));
        assert_eq!(unit("MPa"), Some((Quantity::Pressure, 1e6)));
        assert_eq!(unit("mA"), Some((Quantity::Current, 1e-3)));
        assert_eq!(unit("furlong"), None);
        // case: loose except for m (milli) and M (mega)
        assert_eq!(unit("KN"), Some((Quantity::Force, 1e3)));
        assert_eq!(unit("BAR"), Some((Quantity::Pressure, 1e5)));
        assert_eq!(unit("Mpa"), Some((Quantity::Pressure, 1e6)));
        assert_eq!(unit("ma"), Some((Quantity::Current, 1e-3)));
        for refused in ["MM", "Mm", "mPa", "mpa", "MA", "MS", "Ms", "MBAR", "M/S"] {
            assert_eq!(unit(refused), None, "{refused}");
        }
        // the additions: micro in three spellings, the inch-pound units by their definitions
        for us in ["us", "\u{b5}s", "\u{3bc}s"] {
            assert_eq!(unit(us), Some((Quantity::Time, 1e-6)), "{us}");
        }
        assert_eq!(unit("\u{b5}m"), Some((Quantity::Length, 1e-6)));
        assert_eq!(unit("in/s"), Some((Quantity::Velocity, 0.0254)));
        assert_eq!(unit("daN"), Some((Quantity::Force, 10.0)));
        assert_eq!(unit("mbar"), Some((Quantity::Pressure, 100.0)));
        let (_, lbf) = unit("lbf").unwrap();
        assert!((lbf - 4.4482216152605).abs() < 1e-12, "{lbf}");
        let (_, psi) = unit("psi").unwrap();
        assert!((psi - 6894.757293168361).abs() < 1e-8, "{psi}");
        for c in Column::ALL {
            assert_eq!(Column::from_name(c.name()), Some(c));
            assert_eq!(unit(c.si_unit()).unwrap(), (c.quantity(), 1.0));
        }
    }
}
