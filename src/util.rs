//! Small grouping helpers shared by the study layer and the report: outputs follow the
//! enumeration order of the runs, so groups keep first-appearance order.

/// Distinct items in first-appearance order.
pub fn unique<T: PartialEq>(items: impl IntoIterator<Item = T>) -> Vec<T> {
    let mut v = Vec::new();
    for x in items {
        if !v.contains(&x) {
            v.push(x);
        }
    }
    v
}

/// Items grouped by `key`, groups and members in first-appearance order.
pub fn group_by<K: PartialEq, T>(
    items: impl IntoIterator<Item = T>,
    key: impl Fn(&T) -> K,
) -> Vec<(K, Vec<T>)> {
    let mut groups: Vec<(K, Vec<T>)> = Vec::new();
    for x in items {
        let k = key(&x);
        match groups.iter_mut().find(|(g, _)| *g == k) {
            Some((_, v)) => v.push(x),
            None => groups.push((k, vec![x])),
        }
    }
    groups
}

/// 64-bit FNV-1a hash of `bytes`, printed as 16 hex digits: a stable content key (unlike
/// `std`'s `DefaultHasher`, whose algorithm may change between Rust releases).
pub fn content_hash(bytes: &[u8]) -> String {
    let h = bytes.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    });
    format!("{h:016x}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_matches_its_published_test_vectors() {
        assert_eq!(content_hash(b""), "cbf29ce484222325");
        assert_eq!(content_hash(b"a"), "af63dc4c8601ec8c");
        assert_eq!(content_hash(b"foobar"), "85944171f73967e8");
    }

    #[test]
    fn groups_keep_first_appearance_order() {
        let g = group_by([3, 1, 3, 2, 1], |x| *x);
        assert_eq!(g, vec![(3, vec![3, 3]), (1, vec![1, 1]), (2, vec![2])]);
        assert_eq!(unique([2, 2, 1, 2]), vec![2, 1]);
    }
}
