//! `squeal::modal::release_free_heap` hands freed heap back to the system: memory freed in
//! the middle of a thread's heap (held there by a live neighbour) stays resident until it is
//! called. Its own test binary, so that no other test allocates while the resident set is read.

/// Resident set (MB) from `/proc/self/status`, `None` where there is none.
fn resident_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    Some(line.split_whitespace().nth(1)?.parse::<f64>().ok()? / 1024.0)
}

#[test]
fn freed_heap_in_the_middle_of_an_arena_is_handed_back() {
    const CHUNK_BYTES: usize = 4096;
    const CHUNKS: usize = 65_536; // 256 MB in chunks far below glibc's mmap threshold
                                  // Every 64th chunk stays alive, so the freed ones are not at the top of the heap, where
                                  // glibc would trim them by itself.
    let survivors = std::thread::spawn(|| {
        let mut chunks: Vec<Vec<u8>> = (0..CHUNKS)
            .map(|i| vec![(i % 251) as u8 + 1; CHUNK_BYTES])
            .collect();
        let mut keep = Vec::new();
        for (i, c) in chunks.drain(..).enumerate() {
            if i % 64 == 0 {
                keep.push(c);
            }
        }
        keep
    })
    .join()
    .expect("allocating thread");
    let (Some(before), true) = (resident_mb(), cfg!(target_env = "gnu")) else {
        // No /proc or not glibc: nothing to measure; the call must still be harmless.
        squeal::modal::release_free_heap();
        return;
    };
    assert!(squeal::modal::release_free_heap(), "glibc: the trim ran");
    let after = resident_mb().expect("VmRSS");
    // 252 MB were freed; the survivors' pages (one 4 KB chunk in 64) keep a few MB resident,
    // and page granularity loses a little more. Half of the freed memory is a bound that a
    // no-op (0 MB) cannot meet and the trim (measured ~250 MB) clears with a wide margin.
    assert!(
        before - after > 126.0,
        "resident {before:.0} MB before the release, {after:.0} MB after"
    );
    assert_eq!(survivors.len(), CHUNKS / 64);
    assert!(survivors.iter().all(|c| c[0] != 0));
}
