//! The iteration order of a `std::unordered_map<std::string, T>` of GNU libstdc++
//! (64-bit), which BehaviorTree.CPP uses for a node's ports: the order in which its
//! FileLogger2 writes a node's port attributes and a model's ports.
//!
//! The order follows from the container's rules, modelled here: `std::hash` of a
//! string is libstdc++'s `_Hash_bytes` (MurmurHash2, 64-bit) with seed `0xc70f6907`;
//! a map starts with one bucket and takes 13 on its first insertion (then grows
//! through libstdc++'s prime list when the load factor passes 1); a key goes to the
//! front of its bucket, and a key whose bucket was empty goes to the front of the
//! whole list. A copy keeps the order.

/// libstdc++'s `_Hash_bytes` on 64-bit targets.
#[must_use]
pub fn hash_bytes(bytes: &[u8], seed: u64) -> u64 {
    const MUL: u64 = (0xc6a4_a793_u64 << 32) + 0x5bd1_e995;
    let shift_mix = |v: u64| v ^ (v >> 47);
    let len = bytes.len();
    let aligned = len & !7;
    let mut hash = seed ^ (len as u64).wrapping_mul(MUL);
    for chunk in bytes[..aligned].chunks_exact(8) {
        let mut b = [0u8; 8];
        b.copy_from_slice(chunk);
        let data = shift_mix(u64::from_le_bytes(b).wrapping_mul(MUL)).wrapping_mul(MUL);
        hash ^= data;
        hash = hash.wrapping_mul(MUL);
    }
    let rest = &bytes[aligned..];
    if !rest.is_empty() {
        let mut data = 0u64;
        for &b in rest.iter().rev() {
            data = (data << 8) + u64::from(b);
        }
        hash ^= data;
        hash = hash.wrapping_mul(MUL);
    }
    hash = shift_mix(hash).wrapping_mul(MUL);
    shift_mix(hash)
}

/// `std::hash<std::string>`.
#[must_use]
pub fn string_hash(s: &str) -> u64 {
    hash_bytes(s.as_bytes(), 0xc70f_6907)
}

/// The start of libstdc++'s prime list of bucket counts (past the small sizes).
const PRIMES: &[u64] = &[
    2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53, 59, 61, 67, 71, 73, 79, 83, 89, 97, 103, 109, 113, 127,
    137, 139, 149, 157, 167, 179, 193, 199, 211, 227, 241, 257, 277, 293, 313, 337, 359, 383, 409, 439, 467, 503, 541,
    577, 619, 661, 709, 761, 823, 887, 953, 1031, 1109, 1193, 1289, 1381, 1493, 1613, 1741, 1879, 2029, 2179, 2357,
    2549, 2753, 2971, 3209, 3469, 3739, 4027, 4349, 4703, 5087, 5503, 5953, 6427, 6949, 7517, 8123,
];

const FAST_BUCKETS: [u64; 14] = [2, 2, 2, 3, 5, 5, 7, 7, 11, 11, 11, 11, 13, 13];

/// An insertion-only model of the container: keys in iteration order.
#[derive(Clone, Debug, Default)]
pub struct UnorderedMap {
    /// Keys in iteration order, with their hashes.
    list: Vec<(String, u64)>,
    buckets: u64,
    next_resize: u64,
}

impl UnorderedMap {
    /// An empty map (one bucket).
    #[must_use]
    pub fn new() -> Self {
        Self { list: Vec::new(), buckets: 1, next_resize: 0 }
    }

    /// The keys in iteration order.
    pub fn keys(&self) -> impl Iterator<Item = &str> {
        self.list.iter().map(|(k, _)| k.as_str())
    }

    fn next_bucket_count(&mut self, n: u64) -> u64 {
        if let Some(&b) = FAST_BUCKETS.get(n as usize) {
            if n == 0 {
                return 1;
            }
            self.next_resize = b;
            return b;
        }
        let b = PRIMES[6..].iter().copied().find(|&p| p >= n).unwrap_or(n);
        self.next_resize = b;
        b
    }

    /// Inserts `key` (no effect when present), as `operator[]`, `insert` and `emplace`
    /// do.
    pub fn insert(&mut self, key: &str) {
        if self.list.iter().any(|(k, _)| k == key) {
            return;
        }
        let hash = string_hash(key);
        let elements = self.list.len() as u64;
        if elements + 1 > self.next_resize {
            let min = (elements + 1).max(if self.next_resize == 0 { 11 } else { 0 });
            if min >= self.buckets {
                let n = (min + 1).max(self.buckets * 2);
                let b = self.next_bucket_count(n);
                self.rehash(b);
            } else {
                self.next_resize = self.buckets;
            }
        }
        self.insert_bucket_begin(key.to_string(), hash);
    }

    fn bucket(&self, hash: u64) -> u64 {
        hash % self.buckets
    }

    /// Where a new key goes: before the first key of its bucket when the bucket has
    /// one, else at the front of the list.
    fn insert_bucket_begin(&mut self, key: String, hash: u64) {
        let b = self.bucket(hash);
        let at = self.list.iter().position(|(_, h)| self.bucket(*h) == b).unwrap_or(0);
        self.list.insert(at, (key, hash));
    }

    fn rehash(&mut self, buckets: u64) {
        let old = std::mem::take(&mut self.list);
        self.buckets = buckets;
        // Walk the old list; a node whose bucket is new goes to the front of the list,
        // else to the front of its bucket.
        let mut list: Vec<(String, u64)> = Vec::with_capacity(old.len());
        for (k, h) in old {
            let b = h % buckets;
            match list.iter().position(|(_, x)| x % buckets == b) {
                None => list.insert(0, (k, h)),
                Some(first) => list.insert(first, (k, h)),
            }
        }
        self.list = list;
    }
}

/// The iteration order of a map made by inserting `keys` in this order.
#[must_use]
pub fn order<'a>(keys: impl IntoIterator<Item = &'a str>) -> Vec<String> {
    let mut m = UnorderedMap::new();
    for k in keys {
        m.insert(k);
    }
    m.keys().map(str::to_string).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Orders BehaviorTree.CPP 4.10.0 built with g++ 12 printed (its built-in models in
    /// `builtin-models.xml`: Parallel, Loop*, Switch2, Switch6, SetBlackboard,
    /// Precondition); Switch6 shows a bucket collision.
    #[test]
    fn orders_seen_in_behaviortree_cpp_logs() {
        assert_eq!(order(["success_count", "failure_count"]), ["failure_count", "success_count"]);
        assert_eq!(order(["queue", "if_empty", "value"]), ["value", "if_empty", "queue"]);
        assert_eq!(order(["variable", "case_1", "case_2"]), ["case_2", "case_1", "variable"]);
        assert_eq!(
            order(["variable", "case_1", "case_2", "case_3", "case_4", "case_5", "case_6"]),
            ["case_5", "case_4", "case_6", "case_3", "case_2", "case_1", "variable"]
        );
        assert_eq!(order(["value", "output_key"]), ["output_key", "value"]);
        assert_eq!(order(["if", "else"]), ["else", "if"]);
    }
}
