//! Interning of fixed-width slices (location vectors, zones) in one flat arena, with hashing
//! that needs no allocation: a lookup hashes the candidate slice and compares it in place. The
//! table keeps each slice's hash beside its id, so that growing it hashes no slice again
//! (rehashing the zones was a tenth of `bench timed`).

use hashbrown::{DefaultHashBuilder, HashTable};
use std::hash::{BuildHasher, Hash};

pub struct SliceArena<T> {
    width: usize,
    data: Vec<T>,
    /// Ids with their slices' hashes.
    table: HashTable<(u32, u64)>,
    hasher: DefaultHashBuilder,
}

impl<T: Copy + Eq + Hash> SliceArena<T> {
    pub fn new(width: usize) -> SliceArena<T> {
        SliceArena { width, data: Vec::new(), table: HashTable::new(), hasher: DefaultHashBuilder::default() }
    }

    pub fn len(&self) -> usize {
        self.data.len().checked_div(self.width).unwrap_or(self.table.len())
    }

    pub fn get(&self, id: u32) -> &[T] {
        let start = id as usize * self.width;
        &self.data[start..start + self.width]
    }

    /// The id of `slice`, adding it if new; the flag tells whether it was added.
    pub fn intern(&mut self, slice: &[T]) -> (u32, bool) {
        debug_assert_eq!(slice.len(), self.width);
        let hash = self.hasher.hash_one(slice);
        let (data, width) = (&self.data, self.width);
        let eq = |&(id, _): &(u32, u64)| &data[id as usize * width..id as usize * width + width] == slice;
        if let Some(&(id, _)) = self.table.find(hash, eq) {
            return (id, false);
        }
        let id = self.table.len() as u32;
        self.data.extend_from_slice(slice);
        self.table.insert_unique(hash, (id, hash), |&(_, hash)| hash);
        (id, true)
    }

    /// Bytes held by the arena (data and table), for statistics.
    pub fn heap_bytes(&self) -> usize {
        self.data.capacity() * std::mem::size_of::<T>()
            + self.table.capacity() * (std::mem::size_of::<(u32, u64)>() + 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interning_is_stable_and_deduplicates() {
        let mut a = SliceArena::<u32>::new(3);
        assert_eq!(a.intern(&[1, 2, 3]), (0, true));
        assert_eq!(a.intern(&[3, 2, 1]), (1, true));
        assert_eq!(a.intern(&[1, 2, 3]), (0, false));
        assert_eq!(a.get(1), &[3, 2, 1]);
        assert_eq!(a.len(), 2);
        for i in 0..1000u32 {
            a.intern(&[i, i + 1, i + 2]);
        }
        assert!(!a.intern(&[500, 501, 502]).1);
        let id = a.intern(&[7, 8, 9]).0;
        assert_eq!(a.get(id), &[7, 8, 9]);
    }

    #[test]
    fn zero_width_slices_have_one_id() {
        let mut a = SliceArena::<u32>::new(0);
        assert_eq!(a.intern(&[]), (0, true));
        assert_eq!(a.intern(&[]), (0, false));
        assert_eq!(a.len(), 1);
    }
}
