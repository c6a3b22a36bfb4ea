//! Dataset 164 (units) and conversion of dataset 58 values to SI.
//!
//! Records: 1 `I10,20A1,I10`: units code, description, temperature mode
//! (1 absolute, 2 relative); 2 `3D25.17`: length, force, temperature factors;
//! 3 `D25.17`: temperature offset. A factor is file units per SI unit: to
//! convert a file value to SI, divide by the factor (length 3.28084 for feet).

use super::text;
use super::Function58;

/// The unit system named by the units code of dataset 164.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnitSystem {
    /// 1: SI (meter, newton, °C).
    Si,
    /// 2: British gravitational (foot, pound force, °F).
    BritishGravitational,
    /// 3: metric gravitational (meter, kilogram force, °C).
    MetricGravitational,
    /// 4: British absolute (foot, poundal, °F).
    BritishAbsolute,
    /// 5: millimeter, milli-newton, °C.
    MillimeterMilliNewton,
    /// 6: centimeter, centi-newton, °C.
    CentimeterCentiNewton,
    /// 7: inch, pound force, °F.
    InchPoundForce,
    /// 8: millimeter, kilogram force, °C.
    MillimeterKilogramForce,
    /// 9: user defined (factors only).
    UserDefined,
    /// 10: millimeter, newton, °C.
    MillimeterNewton,
    /// Any other code.
    Other(i32),
}

impl UnitSystem {
    pub fn from_code(code: i32) -> Self {
        match code {
            1 => UnitSystem::Si,
            2 => UnitSystem::BritishGravitational,
            3 => UnitSystem::MetricGravitational,
            4 => UnitSystem::BritishAbsolute,
            5 => UnitSystem::MillimeterMilliNewton,
            6 => UnitSystem::CentimeterCentiNewton,
            7 => UnitSystem::InchPoundForce,
            8 => UnitSystem::MillimeterKilogramForce,
            9 => UnitSystem::UserDefined,
            10 => UnitSystem::MillimeterNewton,
            c => UnitSystem::Other(c),
        }
    }
}

/// Dataset 164: the units of the file's values.
#[derive(Clone, Debug, PartialEq)]
pub struct Units164 {
    pub code: i32,
    pub system: UnitSystem,
    pub description: String,
    /// 1 absolute, 2 relative; 0 if absent.
    pub temperature_mode: i32,
    /// File length units per meter (SI value = file value / factor).
    pub length: f64,
    /// File force units per newton.
    pub force: f64,
    /// File temperature units per kelvin.
    pub temperature: f64,
    /// Temperature offset of the file's temperature scale.
    pub temperature_offset: f64,
}

impl Units164 {
    /// SI units: every factor 1.
    pub fn si() -> Self {
        Units164 {
            code: 1,
            system: UnitSystem::Si,
            description: "SI".into(),
            temperature_mode: 2,
            length: 1.0,
            force: 1.0,
            temperature: 1.0,
            temperature_offset: 0.0,
        }
    }

    /// The factor by which a value with unit exponents (length, force,
    /// temperature) must be multiplied to be in SI.
    pub fn si_factor(
        &self,
        length_exponent: i32,
        force_exponent: i32,
        temperature_exponent: i32,
    ) -> f64 {
        self.length.powi(-length_exponent)
            * self.force.powi(-force_exponent)
            * self.temperature.powi(-temperature_exponent)
    }
}

/// The factor by which the ordinate of `f` must be multiplied to be in SI:
/// numerator exponents (record 9) minus denominator exponents (record 10).
/// Unit labels such as "g" are not interpreted: see [`units_label_si_factor`].
pub fn ordinate_si_factor(f: &Function58, units: &Units164) -> f64 {
    let (n, d) = (&f.numerator_axis, &f.denominator_axis);
    units.si_factor(
        n.length_exponent - d.length_exponent,
        n.force_exponent - d.force_exponent,
        n.temperature_exponent - d.temperature_exponent,
    )
}

/// The factor by which the abscissa of `f` must be multiplied to be in SI
/// (record 8 exponents).
pub fn abscissa_si_factor(f: &Function58, units: &Units164) -> f64 {
    let a = &f.abscissa_axis;
    units.si_factor(a.length_exponent, a.force_exponent, a.temperature_exponent)
}

/// Standard gravity in m/s², for accelerations labelled in g.
pub const STANDARD_GRAVITY: f64 = 9.80665;

/// The SI factor implied by a units label whose quantity the unit exponents do
/// not carry: "g" (standard gravity) and its powers/ratios such as "g/N",
/// "g^2/Hz", "g²/Hz". `None` for labels without g.
pub fn units_label_si_factor(label: &str) -> Option<f64> {
    let l: String = label
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect::<String>()
        .to_lowercase();
    let l = l.trim_start_matches('(');
    let g = l.strip_prefix('g')?;
    let power =
        if g.starts_with("^2") || g.starts_with('²') || g.starts_with("2") || g.starts_with("**2")
        {
            2
        } else if g.is_empty()
            || g.starts_with('/')
            || g.starts_with(')')
            || g.starts_with('*')
            || g.starts_with("rms")
        {
            1
        } else {
            return None; // "gram", "gal", ...
        };
    Some(STANDARD_GRAVITY.powi(power))
}

/// Parses a 164 block (records after the number line).
pub(crate) fn parse(lines: &[text::Line<'_>]) -> Result<Units164, (usize, String)> {
    let Some(first) = lines.first() else {
        return Err((
            0,
            "expected record 1 (I10,20A1,I10: units code, description, temperature mode)".into(),
        ));
    };
    let code = text::parse_int(text::column(first.text, 0, 10))
        .or_else(|| text::tokens(first.text).next().and_then(text::parse_int))
        .ok_or((
            0,
            format!(
                "record 1: expected a units code (I10), found '{}'",
                text::excerpt(first.text)
            ),
        ))?;
    let description = text::text_field(text::trim(text::column(first.text, 10, 30)));
    let temperature_mode = text::parse_int_or_zero(text::column(first.text, 30, 40)).unwrap_or(0);
    let mut values = Vec::with_capacity(4);
    for (k, line) in lines.iter().enumerate().skip(1) {
        text::reals_by_width_or_tokens(line.text, 25, &mut values)
            .map_err(|m| (k, format!("record {}: {m}", k + 1)))?;
    }
    if values.len() < 4 {
        return Err((
            lines.len().saturating_sub(1),
            format!(
                "expected 4 factors (length, force, temperature, temperature offset), found {}",
                values.len()
            ),
        ));
    }
    if let Some((k, v)) = text::first_non_finite(&values) {
        return Err((
            1,
            format!("factor {} is {v}; expected a finite number", k + 1),
        ));
    }
    if values[..3].contains(&0.0) {
        return Err((
            1,
            "length, force and temperature factors must not be 0".into(),
        ));
    }
    let code = i32::try_from(code).map_err(|_| (0, format!("units code {code} out of range")))?;
    Ok(Units164 {
        code,
        system: UnitSystem::from_code(code),
        description,
        temperature_mode: temperature_mode as i32,
        length: values[0],
        force: values[1],
        temperature: values[2],
        temperature_offset: values[3],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn g_labels() {
        assert_eq!(units_label_si_factor("g"), Some(STANDARD_GRAVITY));
        assert_eq!(units_label_si_factor("g/N"), Some(STANDARD_GRAVITY));
        assert_eq!(
            units_label_si_factor("g^2/Hz"),
            Some(STANDARD_GRAVITY * STANDARD_GRAVITY)
        );
        assert_eq!(
            units_label_si_factor("g²/Hz"),
            Some(STANDARD_GRAVITY * STANDARD_GRAVITY)
        );
        assert_eq!(units_label_si_factor("gram"), None);
        assert_eq!(units_label_si_factor("m/s^2"), None);
    }

    #[test]
    fn feet_to_meters() {
        let u = Units164 {
            length: 3.28083989501312,
            ..Units164::si()
        };
        // Acceleration in ft/s^2 per lbf → (m/s^2)/N: length exponent 1.
        assert!((u.si_factor(1, 0, 0) - 0.3048).abs() < 1e-12);
    }
}
