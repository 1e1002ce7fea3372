//! "Did you mean ...?": the closest candidate to a misspelled name, key or keyword.

/// Edit distance between two strings (by chars) counting an adjacent transposition as one edit
/// (optimal string alignment), since swapped letters are the most common typo (`mian` for
/// `main`). Names longer than 64 chars are never close to anything.
pub fn edit_distance(a: &str, b: &str) -> usize {
    distance(a, b, |x, y| x == y)
}

/// [`edit_distance`] with ASCII letters compared without case (`a.to_ascii_lowercase()`
/// against `b.to_ascii_lowercase()`, without making either).
fn edit_distance_ignoring_ascii_case(a: &str, b: &str) -> usize {
    distance(a, b, |x, y| x.eq_ignore_ascii_case(&y))
}

/// The distance of `a` and `b` with chars equal by `same`: by bytes when both are ASCII (a
/// byte is a char there), else by chars. No allocation for ASCII names: a did-you-mean over
/// 100 names for each of 1,000 unknown names (a renamed material) made 600,000 before
/// (2026-11-26, sixth session).
fn distance(a: &str, b: &str, same: impl Fn(char, char) -> bool) -> usize {
    if a.is_ascii() && b.is_ascii() {
        let (a, b) = (a.as_bytes(), b.as_bytes());
        return rows(a.len(), b.len(), |i, j| {
            same(char::from(a[i]), char::from(b[j]))
        });
    }
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    rows(a.len(), b.len(), |i, j| same(a[i], b[j]))
}

/// The optimal string alignment distance of sequences of lengths `n` and `m` whose elements
/// `i` and `j` are equal when `eq(i, j)`; `usize::MAX` past 64.
fn rows(n: usize, m: usize, eq: impl Fn(usize, usize) -> bool) -> usize {
    const MAX: usize = 64;
    if n > MAX || m > MAX {
        return usize::MAX;
    }
    // Three rolling rows: i-2, i-1, i. Bytes (a distance is at most 64): rows of `usize`
    // were 1.5 KB to clear per pair, most of a did-you-mean's cost for short names.
    let mut before = [0u8; MAX + 1];
    let mut prev = [0u8; MAX + 1];
    let mut cur = [0u8; MAX + 1];
    for (j, p) in prev.iter_mut().enumerate().take(m + 1) {
        *p = j as u8;
    }
    for i in 0..n {
        cur[0] = i as u8 + 1;
        for j in 0..m {
            let cost = u8::from(!eq(i, j));
            let mut d = (prev[j] + cost).min(prev[j + 1] + 1).min(cur[j] + 1);
            if i > 0 && j > 0 && eq(i, j - 1) && eq(i - 1, j) {
                d = d.min(before[j - 1] + 1);
            }
            cur[j + 1] = d;
        }
        std::mem::swap(&mut before, &mut prev);
        std::mem::swap(&mut prev, &mut cur);
    }
    usize::from(prev[m])
}

/// The candidate closest to `name`, if it is close enough to be a plausible typo: at most one
/// edit for short names, two for names of 5+ chars, three for 9+ (case differences are free).
pub fn did_you_mean<'a, I>(name: &str, candidates: I) -> Option<&'a str>
where
    I: IntoIterator<Item = &'a str>,
{
    let limit = match name.chars().count() {
        0..=4 => 1,
        5..=8 => 2,
        _ => 3,
    };
    candidates
        .into_iter()
        .filter(|c| *c != name)
        .map(|c| (edit_distance_ignoring_ascii_case(name, c), c))
        .filter(|(d, _)| *d <= limit)
        .min_by_key(|(d, c)| (*d, *c))
        .map(|(_, c)| c)
}

/// "did you mean `x`?" or, when nothing is close, the list of valid choices.
pub fn help_for(name: &str, candidates: &[&str], what: &str) -> String {
    match did_you_mean(name, candidates.iter().copied()) {
        Some(best) => format!("did you mean `{best}`?"),
        None if candidates.is_empty() => format!("there are no {what} to choose from"),
        None => format!("valid {what}: {}", list(candidates)),
    }
}

/// `a`, `b`, `c` as one string.
pub fn list(items: &[&str]) -> String {
    items
        .iter()
        .map(|i| format!("`{i}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The distance as it was computed before the allocation-free rows (chars collected, three
    /// rows allocated): the oracle for [`edit_distance`].
    fn reference_distance(a: &str, b: &str) -> usize {
        let a: Vec<char> = a.chars().collect();
        let b: Vec<char> = b.chars().collect();
        if a.len() > 64 || b.len() > 64 {
            return usize::MAX;
        }
        let mut before: Vec<usize> = vec![0; b.len() + 1];
        let mut prev: Vec<usize> = (0..=b.len()).collect();
        let mut cur = vec![0; b.len() + 1];
        for i in 0..a.len() {
            cur[0] = i + 1;
            for j in 0..b.len() {
                let cost = usize::from(a[i] != b[j]);
                let mut d = (prev[j] + cost).min(prev[j + 1] + 1).min(cur[j] + 1);
                if i > 0 && j > 0 && a[i] == b[j - 1] && a[i - 1] == b[j] {
                    d = d.min(before[j - 1] + 1);
                }
                cur[j + 1] = d;
            }
            std::mem::swap(&mut before, &mut prev);
            std::mem::swap(&mut prev, &mut cur);
        }
        prev[b.len()]
    }

    #[test]
    fn distances_are_the_allocating_reference_ones_with_and_without_case() {
        let words = [
            "",
            "a",
            "m0",
            "m0x",
            "M0",
            "mian",
            "main",
            "Main",
            "kitten",
            "sitting",
            "gloss",
            "glossy",
            "GLOSSY",
            "naïve",
            "naive",
            "NAÏVE",
            "ünknown",
            "unknown",
            "ab",
            "ba",
            "abc",
            "cab",
            &"x".repeat(64),
            &"x".repeat(65),
            &"y".repeat(64),
        ];
        for a in words {
            for b in words {
                assert_eq!(edit_distance(a, b), reference_distance(a, b), "{a} {b}");
                let lower = reference_distance(&a.to_ascii_lowercase(), &b.to_ascii_lowercase());
                assert_eq!(edit_distance_ignoring_ascii_case(a, b), lower, "{a} {b}");
            }
        }
    }

    #[test]
    fn distance_counts_edits() {
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("same", "same"), 0);
        assert_eq!(
            edit_distance("mian", "main"),
            1,
            "a swap of neighbours is one edit"
        );
        assert_eq!(
            edit_distance("ca", "abc"),
            3,
            "optimal string alignment, not full Damerau"
        );
    }

    #[test]
    fn suggests_close_names_only() {
        let keys = ["diffuse", "specular", "shininess", "ambient"];
        assert_eq!(did_you_mean("difuse", keys), Some("diffuse"));
        assert_eq!(did_you_mean("shinyness", keys), Some("shininess"));
        assert_eq!(did_you_mean("Diffuse", keys), Some("diffuse"));
        assert_eq!(did_you_mean("colour", keys), None);
        assert_eq!(
            did_you_mean("materail", ["material", "mesh"]),
            Some("material")
        );
    }

    #[test]
    fn help_lists_keys_when_nothing_is_close() {
        let h = help_for("zzz", &["eye", "target"], "keys");
        assert_eq!(h, "valid keys: `eye`, `target`");
    }
}
