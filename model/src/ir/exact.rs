//! Fixed-size lists read exactly. TOML's deserializer hands serde's `[T; N]` the first N
//! elements of a longer list and drops the rest (the array impl reads N and stops), so
//! `cog = [0, 0, 0.45, 7]` read as `[0, 0, 0.45]` without a word. Every fixed-size field of the
//! model and of the modal data names [`exact`] in `deserialize_with`: a list of any other length
//! is an error ("invalid length 4, expected an array of length 3", serde's words), which the readers place
//! at the field (`ir::toml_file`, `ir::modal::read_file`).

use serde::de::{self, DeserializeSeed, Deserializer, SeqAccess, Visitor};
use std::fmt;
use std::marker::PhantomData;

/// A value whose lists, at any depth, must have the length its type says.
pub trait Exact<'de>: Sized {
    fn exact<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error>;
}

impl<'de> Exact<'de> for f64 {
    fn exact<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        serde::Deserialize::deserialize(d)
    }
}

impl<'de, T: Exact<'de>> Exact<'de> for Vec<T> {
    fn exact<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_seq(List::<T>(None, PhantomData))
    }
}

impl<'de, T: Exact<'de>, const N: usize> Exact<'de> for [T; N] {
    fn exact<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = d.deserialize_seq(List::<T>(Some(N), PhantomData))?;
        // The visitor has checked the length.
        v.try_into()
            .map_err(|_| de::Error::custom("a list of the wrong length"))
    }
}

/// An optional field is present when this is called (`#[serde(default)]` gives the `None`).
impl<'de, T: Exact<'de>> Exact<'de> for Option<T> {
    fn exact<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        T::exact(d).map(Some)
    }
}

/// `#[serde(deserialize_with = "exact")]` on a fixed-size field.
pub fn exact<'de, D: Deserializer<'de>, T: Exact<'de>>(d: D) -> Result<T, D::Error> {
    T::exact(d)
}

/// A list of `T`, of exactly `.0` elements when given.
struct List<T>(Option<usize>, PhantomData<T>);

impl<'de, T: Exact<'de>> Visitor<'de> for List<T> {
    type Value = Vec<T>;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self.0 {
            Some(n) => write!(f, "an array of length {n}"),
            None => write!(f, "a list"),
        }
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<T>, A::Error> {
        let mut v = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(1 << 16));
        while let Some(x) = seq.next_element_seed(Element::<T>(PhantomData))? {
            v.push(x);
        }
        match self.0 {
            Some(n) if v.len() != n => Err(de::Error::invalid_length(v.len(), &self)),
            _ => Ok(v),
        }
    }
}

struct Element<T>(PhantomData<T>);

impl<'de, T: Exact<'de>> DeserializeSeed<'de> for Element<T> {
    type Value = T;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<T, D::Error> {
        T::exact(d)
    }
}

#[cfg(test)]
mod tests {
    use super::exact;
    use serde::Deserialize;

    #[derive(Debug, Deserialize, PartialEq)]
    struct S {
        #[serde(deserialize_with = "exact")]
        v: [f64; 3],
        #[serde(default, deserialize_with = "exact")]
        o: Option<[f64; 2]>,
        #[serde(default, deserialize_with = "exact")]
        m: [[f64; 2]; 2],
        #[serde(default, deserialize_with = "exact")]
        l: [Vec<f64>; 2],
    }

    #[test]
    fn a_list_of_another_length_is_refused_at_any_depth() {
        let ok: S = toml::from_str("v = [1, 2, 3.5]\nm = [[1, 2], [3, 4]]\nl = [[], [1]]").unwrap();
        assert_eq!(ok.v, [1.0, 2.0, 3.5]);
        assert_eq!(ok.o, None);
        assert_eq!(ok.l, [vec![], vec![1.0]]);
        for bad in [
            "v = [1, 2, 3, 4]",
            "v = [1, 2]",
            "v = [1, 2, 3]\no = [1, 2, 3]",
            "v = [1, 2, 3]\nm = [[1, 2], [3, 4, 5]]",
            "v = [1, 2, 3]\nm = [[1, 2], [3, 4], [5, 6]]",
            "v = [1, 2, 3]\nl = [[], [1], [2]]",
        ] {
            let e = toml::from_str::<S>(bad).unwrap_err();
            assert!(
                e.message().contains("expected an array of length"),
                "{bad}: {e}"
            );
        }
    }
}
