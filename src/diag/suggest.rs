//! "Did you mean ...?": the closest candidate to a misspelled name, key or keyword.

/// Edit distance between two strings (by chars) counting an adjacent transposition as one edit
/// (optimal string alignment), since swapped letters are the most common typo (`mian` for
/// `main`). Names longer than 64 chars are never close to anything.
pub fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    if a.len() > 64 || b.len() > 64 {
        return usize::MAX;
    }
    // Three rolling rows: i-2, i-1, i.
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

/// The candidate closest to `name`, if it is close enough to be a plausible typo: at most one
/// edit for short names, two for names of 5+ chars, three for 9+ (case differences are free).
pub fn did_you_mean<'a, I>(name: &str, candidates: I) -> Option<&'a str>
where
    I: IntoIterator<Item = &'a str>,
{
    let lower = name.to_ascii_lowercase();
    let limit = match name.chars().count() {
        0..=4 => 1,
        5..=8 => 2,
        _ => 3,
    };
    candidates
        .into_iter()
        .filter(|c| *c != name)
        .map(|c| (edit_distance(&lower, &c.to_ascii_lowercase()), c))
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
