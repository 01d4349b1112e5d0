//! Typed ids: zero-cost `u32` newtypes, one per kind of table index, so that a location id
//! cannot be passed where a state id is meant.
//!
//! [`id_type!`] defines one: `#[repr(transparent)]` over `u32`, `Copy`, `Eq`, `Ord`, `Hash`,
//! `Debug` and `Display` printing the bare number (as the `u32` did, so dumps and messages are
//! unchanged). `new(usize)` and `index() -> usize` convert from and to a table position,
//! `from_raw(u32)` and `raw() -> u32` from and to the stored number. A type that crosses serde
//! derives `Serialize`/`Deserialize` with `#[serde(transparent)]` in the attributes it is given,
//! so its JSON stays a plain number. Absence is `Option<Id>`, or a named constant where a table
//! stores it in place.

/// Defines a `#[repr(transparent)]` `u32` newtype id; the attributes given (docs, extra
/// derives such as serde's with `#[serde(transparent)]`) go on the struct.
macro_rules! id_type {
    ($(#[$meta:meta])* $vis:vis struct $name:ident;) => {
        $(#[$meta])*
        #[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
        #[repr(transparent)]
        $vis struct $name(u32);

        #[allow(dead_code)]
        impl $name {
            /// The id of table position `index` (which fits in a `u32`).
            #[inline(always)]
            pub const fn new(index: usize) -> $name {
                debug_assert!(index <= u32::MAX as usize);
                $name(index as u32)
            }

            /// The id whose stored number is `raw`.
            #[inline(always)]
            pub const fn from_raw(raw: u32) -> $name {
                $name(raw)
            }

            /// The table position of this id.
            #[inline(always)]
            pub const fn index(self) -> usize {
                self.0 as usize
            }

            /// The stored number of this id.
            #[inline(always)]
            pub const fn raw(self) -> u32 {
                self.0
            }
        }

        impl ::std::fmt::Debug for $name {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                ::std::fmt::Debug::fmt(&self.0, f)
            }
        }

        impl ::std::fmt::Display for $name {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                ::std::fmt::Display::fmt(&self.0, f)
            }
        }
    };
}

pub(crate) use id_type;

#[cfg(test)]
mod tests {
    id_type! {
        /// A test id.
        #[derive(serde::Serialize, serde::Deserialize)]
        #[serde(transparent)]
        struct TestId;
    }

    #[test]
    fn ids_are_their_number() {
        let id = TestId::new(7);
        assert_eq!(id.index(), 7);
        assert_eq!(id.raw(), 7);
        assert_eq!(TestId::from_raw(7), id);
        assert_eq!(format!("{id} {id:?} {:?}", Some(id)), "7 7 Some(7)");
        assert_eq!(serde_json::to_string(&id).unwrap(), "7");
        assert_eq!(serde_json::from_str::<TestId>("7").unwrap(), id);
        assert_eq!(std::mem::size_of::<TestId>(), 4);
        assert!(TestId::new(1) < TestId::new(2));
    }
}
