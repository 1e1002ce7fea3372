//! Stage 2, check, incrementally: the placement phase's output (diagnostics, IR objects) is one
//! run per statement, in statement order, each as long as its [`StmtRecord`] says; a
//! re-check gives some statements new runs, and these functions put them in place of the old
//! ones, every other item kept (its spans moved by the edit).
//!
//! [`merge_runs`] makes a new list (the diagnostics: a few thousand at most);
//! [`merge_runs_in_place`] moves the kept items within the list they are in (the IR's
//! objects: 15 MB for issue 22's 100,000, where a fresh list cost its page faults on every
//! edit that changes a run's length, such as a rename that drops 1,000 objects; 2026-11-26,
//! seventh session).

use super::super::StmtRecord;

/// `items`, one run per statement (`count` of its record long, in statement order), with the
/// runs of the statements in `new` (index → run) put in place of theirs and every other item
/// kept where `keep` (which moves its spans) allows; `None` when the counts do not add up or
/// `keep` refuses one.
pub(super) fn merge_runs<T>(
    items: Vec<T>,
    records: &[StmtRecord],
    count: fn(&StmtRecord) -> u32,
    new: impl Iterator<Item = (usize, Vec<T>)>,
    mut keep: impl FnMut(&mut T) -> bool,
) -> Option<Vec<T>> {
    let mut out = Vec::with_capacity(items.len());
    let mut items = items.into_iter();
    let mut ok = true;
    let mut next = 0;
    let mut take = |n: usize, out: &mut Vec<T>, items: &mut std::vec::IntoIter<T>| {
        for mut item in items.by_ref().take(n) {
            ok &= keep(&mut item);
            out.push(item);
        }
    };
    for (i, run) in new {
        let before: usize = records
            .get(next..i)?
            .iter()
            .map(|r| count(r) as usize)
            .sum();
        let old = count(records.get(i)?) as usize;
        if items.len() < before + old {
            return None;
        }
        take(before, &mut out, &mut items);
        items.by_ref().take(old).for_each(drop);
        out.extend(run);
        next = i + 1;
    }
    let rest = items.len();
    take(rest, &mut out, &mut items);
    ok.then_some(out)
}

/// A stretch of kept items: where it was and where it goes.
struct Kept {
    from: usize,
    len: usize,
    to: usize,
}

/// [`merge_runs`] within `items` itself: the kept stretches are moved (each once, by
/// `copy_within`) to where the new runs' lengths put them, the new runs copied into the gaps,
/// and the list grown (with `filler`, all overwritten) or cut to its new length. No second
/// list. `None` (`items` then unspecified) when the counts do not add up or `keep` refuses one.
pub(super) fn merge_runs_in_place<T: Copy>(
    items: &mut Vec<T>,
    records: &[StmtRecord],
    count: fn(&StmtRecord) -> u32,
    new: impl Iterator<Item = (usize, Vec<T>)>,
    mut keep: impl FnMut(&mut T) -> bool,
    filler: T,
) -> Option<()> {
    // Where each new run goes and which stretches are kept between them.
    let mut kept = Vec::new();
    let mut runs = Vec::new();
    let (mut next, mut from, mut to) = (0, 0, 0);
    for (i, run) in new {
        let before: usize = records
            .get(next..i)?
            .iter()
            .map(|r| count(r) as usize)
            .sum();
        let old = count(records.get(i)?) as usize;
        if items.len() < from + before + old {
            return None;
        }
        kept.push(Kept {
            from,
            len: before,
            to,
        });
        to += before;
        let len = run.len();
        runs.push((to, run));
        (from, to, next) = (from + before + old, to + len, i + 1);
    }
    let rest = items.len() - from;
    kept.push(Kept {
        from,
        len: rest,
        to,
    });
    let new_len = to + rest;
    if new_len > items.len() {
        items.resize(new_len, filler);
    }
    // Stretches moving left, from the left; then those moving right, from the right: each
    // one's destination is then free (its old items already moved, or dropped ones).
    for k in kept.iter().filter(|k| k.to < k.from) {
        items.copy_within(k.from..k.from + k.len, k.to);
    }
    for k in kept.iter().rev().filter(|k| k.to > k.from) {
        items.copy_within(k.from..k.from + k.len, k.to);
    }
    for (at, run) in runs {
        items.get_mut(at..at + run.len())?.copy_from_slice(&run);
    }
    items.truncate(new_len);
    let mut ok = true;
    for k in &kept {
        for item in items.get_mut(k.to..k.to + k.len)? {
            ok &= keep(item);
        }
    }
    ok.then_some(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn records(counts: &[u32]) -> Vec<StmtRecord> {
        counts
            .iter()
            .map(|&objects| StmtRecord {
                object: true,
                setting: false,
                diags: 0,
                objects,
                mesh: None,
                material: None,
            })
            .collect()
    }

    /// Seeded runs of every length (0 to 3) replaced by runs of every length, in place and by
    /// a new list: the same items, kept ones moved by `keep` (+1000) and new ones as given.
    #[test]
    fn in_place_gives_what_a_new_list_gives() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = |n: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % n
        };
        for _ in 0..2000 {
            let counts: Vec<u32> = (0..next(12)).map(|_| next(4) as u32).collect();
            let total: u32 = counts.iter().sum();
            let items: Vec<u32> = (0..total).collect();
            let mut changed: Vec<(usize, Vec<u32>)> = Vec::new();
            for i in 0..counts.len() {
                if next(3) == 0 {
                    let run = (0..next(5)).map(|k| 10_000 + 10 * i as u32 + k as u32);
                    changed.push((i, run.collect()));
                }
            }
            let records = records(&counts);
            let keep = |x: &mut u32| {
                *x += 1000;
                true
            };
            let want = merge_runs(
                items.clone(),
                &records,
                |r| r.objects,
                changed.clone().into_iter(),
                keep,
            );
            let mut got = items.clone();
            let done = merge_runs_in_place(
                &mut got,
                &records,
                |r| r.objects,
                changed.clone().into_iter(),
                keep,
                u32::MAX,
            );
            assert_eq!(done.map(|()| got), want, "{counts:?} {changed:?}");
        }
    }

    /// Counts that do not add up, or a refused item, give `None`, as a new list does.
    #[test]
    fn counts_that_do_not_add_up_or_a_refusal_give_none() {
        let records = records(&[2, 2]);
        let mut items = vec![1u32, 2, 3];
        let run = || std::iter::once((1, vec![9u32]));
        assert!(
            merge_runs_in_place(&mut items, &records, |r| r.objects, run(), |_| true, 0).is_none()
        );
        let mut items = vec![1u32, 2, 3, 4];
        let refuse = |x: &mut u32| *x != 1;
        assert!(
            merge_runs_in_place(&mut items, &records, |r| r.objects, run(), refuse, 0).is_none()
        );
        let mut items = vec![1u32, 2, 3, 4];
        let out_of_order = [(1, vec![]), (0, vec![])].into_iter();
        assert!(merge_runs_in_place(
            &mut items,
            &records,
            |r| r.objects,
            out_of_order,
            |_| true,
            0
        )
        .is_none());
    }
}
