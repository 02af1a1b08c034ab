//! Numbers written for people.

/// Numbers as a comma-separated list for people: `1.6, 1.6, 0`.
pub fn list<T: std::fmt::Display>(v: &[T]) -> String {
    v.iter()
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}
