//! Data parallelism behind one small interface, with a serial shim.
//!
//! With the `parallel` feature (default) the helpers run on rayon; without it they
//! run in order on the calling thread. Every helper keeps input order in its
//! output, so results never depend on the number of threads.

/// Runs `f` on a pool of `threads` threads (all cores when `None`, never
/// more than the cores: [`thread_count`]), so a call
/// from Python or the CLI can bound its parallelism without touching the global
/// pool.
///
/// # Errors
/// [`crate::Error::InvalidParam`] for `Some(0)` threads or when the pool cannot start.
pub fn with_threads<T: Send>(
    threads: Option<usize>,
    f: impl FnOnce() -> T + Send,
) -> crate::Result<T> {
    let n = thread_count(threads)?;
    #[cfg(feature = "parallel")]
    {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| crate::Error::InvalidParam {
                name: "threads",
                reason: format!("cannot start a thread pool: {e}"),
            })?;
        Ok(pool.install(f))
    }
    #[cfg(not(feature = "parallel"))]
    {
        Ok(f())
    }
}

/// The number of threads `threads` asks for, at most the machine's cores
/// (all of them for `None`): more threads than cores mesh no faster, and a
/// request of thousands (a typo, or a pool per file) would start thousands
/// of threads.
///
/// # Errors
/// [`crate::Error::InvalidParam`] for `Some(0)`.
pub fn thread_count(threads: Option<usize>) -> crate::Result<usize> {
    let cores = std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get);
    match threads {
        Some(0) => Err(crate::Error::InvalidParam {
            name: "threads",
            reason: "must be at least 1".to_owned(),
        }),
        Some(n) => Ok(n.min(cores)),
        None => Ok(cores),
    }
}

/// `items.iter().map(f).collect()`, in parallel when available, order kept.
pub fn map<T: Sync, U: Send>(items: &[T], f: impl Fn(&T) -> U + Sync + Send) -> Vec<U> {
    let mut out = Vec::with_capacity(items.len());
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        items.par_iter().map(f).collect_into_vec(&mut out);
    }
    #[cfg(not(feature = "parallel"))]
    {
        out.extend(items.iter().map(f));
    }
    out
}

/// `(0..n).flat_map(f).collect()`, in parallel when available, order kept.
pub fn flat_map_range<U: Send>(n: usize, f: impl Fn(usize) -> Vec<U> + Sync + Send) -> Vec<U> {
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        (0..n).into_par_iter().flat_map_iter(f).collect()
    }
    #[cfg(not(feature = "parallel"))]
    {
        (0..n).flat_map(f).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn order_is_kept_whatever_the_thread_count() {
        let items: Vec<u32> = (0..10_000).collect();
        let one = with_threads(Some(1), || map(&items, |x| x * 2)).unwrap();
        let many = with_threads(Some(4), || map(&items, |x| x * 2)).unwrap();
        assert_eq!(one, many);
        let two = with_threads(Some(2), || map(&items, |x| x * 2)).unwrap();
        assert_eq!(two, one);
        let fm = with_threads(Some(3), || flat_map_range(100, |i| vec![i; i % 3])).unwrap();
        let serial: Vec<usize> = (0..100).flat_map(|i| vec![i; i % 3]).collect();
        assert_eq!(fm, serial);
        assert!(with_threads(Some(0), || ()).is_err());
    }

    #[test]
    fn thread_requests_are_capped_at_the_cores() {
        let cores = thread_count(None).unwrap();
        assert_eq!(thread_count(Some(10_000)).unwrap(), cores);
        assert_eq!(thread_count(Some(1)).unwrap(), 1);
        #[cfg(feature = "parallel")]
        assert_eq!(
            with_threads(Some(10_000), rayon::current_num_threads).unwrap(),
            cores
        );
    }
}
