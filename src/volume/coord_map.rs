//! A small open-addressing hash map from integer coordinates to u32, used for
//! the per-lookup brick and tile tables: no allocation per lookup and a
//! multiply-xor hash that is much cheaper than SipHash.

use glam::IVec3;

const EMPTY: u32 = u32::MAX;

/// Maps an `IVec3` key to a `u32` (never `u32::MAX`).
#[derive(Debug, Clone, Default)]
pub(crate) struct CoordMap {
    keys: Vec<IVec3>,
    vals: Vec<u32>,
    len: usize,
}

#[inline]
fn hash(k: IVec3) -> u64 {
    let h = (k.x as u32 as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (k.y as u32 as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
        ^ (k.z as u32 as u64).wrapping_mul(0x1656_67B1_9E37_79F9);
    h ^ (h >> 29)
}

impl CoordMap {
    /// A map sized for `n` keys at load factor ≤ 1/2.
    pub(crate) fn with_capacity(n: usize) -> Self {
        if n == 0 {
            return CoordMap::default();
        }
        let cap = (2 * n).next_power_of_two().max(8);
        CoordMap {
            keys: vec![IVec3::ZERO; cap],
            vals: vec![EMPTY; cap],
            len: 0,
        }
    }

    /// Number of keys.
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.len
    }

    /// Inserts; returns false (and changes nothing) if the key is present or the map is full.
    pub(crate) fn insert(&mut self, k: IVec3, v: u32) -> bool {
        if self.vals.is_empty() || v == EMPTY || 2 * (self.len + 1) > self.vals.len() {
            return false;
        }
        let mask = self.vals.len() - 1;
        let mut i = hash(k) as usize & mask;
        loop {
            if self.vals[i] == EMPTY {
                self.keys[i] = k;
                self.vals[i] = v;
                self.len += 1;
                return true;
            }
            if self.keys[i] == k {
                return false;
            }
            i = (i + 1) & mask;
        }
    }

    /// The value for `k`.
    #[inline]
    pub(crate) fn get(&self, k: IVec3) -> Option<u32> {
        if self.len == 0 {
            return None;
        }
        let mask = self.vals.len() - 1;
        let mut i = hash(k) as usize & mask;
        loop {
            let v = self.vals[i];
            if v == EMPTY {
                return None;
            }
            if self.keys[i] == k {
                return Some(v);
            }
            i = (i + 1) & mask;
        }
    }

    /// Heap bytes used.
    pub(crate) fn memory_bytes(&self) -> usize {
        self.keys.capacity() * std::mem::size_of::<IVec3>() + self.vals.capacity() * 4
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn insert_get_and_duplicates() {
        let mut m = CoordMap::with_capacity(100);
        for i in 0..100 {
            assert!(m.insert(IVec3::new(i, -i, i * 7), i as u32));
        }
        assert!(!m.insert(IVec3::new(3, -3, 21), 5));
        for i in 0..100 {
            assert_eq!(m.get(IVec3::new(i, -i, i * 7)), Some(i as u32));
        }
        assert_eq!(m.get(IVec3::new(1, 1, 1)), None);
        assert_eq!(CoordMap::default().get(IVec3::ZERO), None);
        assert_eq!(m.len(), 100);
    }
}
