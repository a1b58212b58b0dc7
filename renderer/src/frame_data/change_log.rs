//! The log of an instance table's changes: which instance each recent revision touched, so
//! passes catch up with only what changed since the revision they last followed.

/// The instance of every change since revision `start`: entry `i` made revision
/// `start + i + 1`. It keeps at most [`ChangeLog::CAP`] changes, dropping the older half when
/// full: passes follow every frame, so they lag by one frame's edits, and one that lags by
/// more than the log holds walks every instance instead.
#[derive(Debug, Clone, Default)]
pub(super) struct ChangeLog {
    entries: Vec<u32>,
    start: u64,
}

impl ChangeLog {
    const CAP: usize = 1 << 16;

    pub(super) fn record(&mut self, instance: u32) {
        if self.entries.len() >= Self::CAP {
            let dropped = self.entries.len() / 2;
            self.entries.drain(..dropped);
            self.start += dropped as u64;
        }
        self.entries.push(instance);
    }

    pub(super) fn since(&self, revision: u64) -> Option<&[u32]> {
        let from = usize::try_from(revision.checked_sub(self.start)?).ok()?;
        self.entries.get(from..)
    }
}

#[cfg(test)]
mod tests {
    use super::ChangeLog;

    #[test]
    fn the_change_log_names_the_changes_since_a_revision_until_it_forgets_them() {
        let mut log = ChangeLog::default();
        assert_eq!(log.since(0), Some(&[][..]));
        for i in 0..5 {
            log.record(10 + i);
        }
        assert_eq!(log.since(0), Some(&[10, 11, 12, 13, 14][..]));
        assert_eq!(log.since(3), Some(&[13, 14][..]));
        assert_eq!(log.since(5), Some(&[][..]));
        assert_eq!(log.since(6), None, "a revision the table never had");
        // Past its capacity it drops the older half: revisions before that are forgotten.
        let total = ChangeLog::CAP as u64 + 10;
        for i in 5..total {
            log.record(i as u32);
        }
        assert_eq!(log.since(0), None);
        assert_eq!(
            log.since(total - 2),
            Some(&[total as u32 - 2, total as u32 - 1][..])
        );
        let oldest_kept = total - log.entries.len() as u64;
        assert!(log.since(oldest_kept).is_some());
        assert!(log.since(oldest_kept - 1).is_none());
        assert!(log.entries.len() <= ChangeLog::CAP);
    }
}
