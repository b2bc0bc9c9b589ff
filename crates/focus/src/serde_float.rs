//! Floats that may be infinite, for formats without infinities (JSON writes
//! them as `null` and cannot read them back): a finite value as a number,
//! `±∞` as the strings `"inf"` and `"-inf"`.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

#[derive(Serialize, Deserialize)]
#[serde(untagged)]
enum Repr<'a> {
    Number(f64),
    Name(&'a str),
}

/// Serializes `x`, naming an infinity.
pub(crate) fn serialize<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
    match *x {
        f64::INFINITY => Repr::Name("inf"),
        f64::NEG_INFINITY => Repr::Name("-inf"),
        x => Repr::Number(x),
    }
    .serialize(s)
}

/// Reads a number or a named infinity.
pub(crate) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    match Repr::deserialize(d)? {
        Repr::Number(x) => Ok(x),
        Repr::Name("inf") => Ok(f64::INFINITY),
        Repr::Name("-inf") => Ok(f64::NEG_INFINITY),
        Repr::Name(other) => Err(serde::de::Error::custom(format!("expected a number, \"inf\" or \"-inf\", not {other:?}"))),
    }
}

/// The same for a pair.
pub(crate) mod pair {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    #[derive(Serialize, Deserialize)]
    struct Pair(#[serde(with = "super")] f64, #[serde(with = "super")] f64);

    pub(crate) fn serialize<S: Serializer>(x: &[f64; 2], s: S) -> Result<S::Ok, S::Error> {
        Pair(x[0], x[1]).serialize(s)
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 2], D::Error> {
        let Pair(a, b) = Pair::deserialize(d)?;
        Ok([a, b])
    }
}
