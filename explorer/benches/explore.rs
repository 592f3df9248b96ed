//! Explorer timings: the full enumeration of the four [G] §5.2 families at K = 3 (target: under
//! 10 s in release mode on 2 cores), and an exhaustive search on three symbols.

use lsubdiv_explorer::{enumerate, search, Enumeration, Family, Search};
use std::time::Instant;

fn main() {
    let mut times = Vec::new();
    let mut rows = 0;
    for _ in 0..3 {
        let t = Instant::now();
        rows = Family::ALL
            .iter()
            .map(|&f| {
                enumerate(f, Enumeration::default())
                    .expect("enumerates")
                    .len()
            })
            .sum::<usize>();
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    println!(
        "enumerate, four families, K = 3: {rows} systems listed, median {:.3} s (target < 10 s, ratio {:.1}x under)",
        times[1],
        10.0 / times[1]
    );
    let opts = Search {
        symbols: 3,
        max_word_len: 3,
        rho_min: None,
        rho_max: None,
        max_masks: None,
        require_surface: false,
        include_integer: false,
        asymmetric: false,
        limit: u64::MAX,
        degree: 3,
    };
    let t = Instant::now();
    let found = search(&opts, &|_, _| {}).expect("searches");
    println!(
        "search, 3 symbols, words up to 3: {} rule sets, {} candidates, front of {}, {:.3} s on {} threads",
        found.examined,
        found.candidates,
        found.front.len(),
        t.elapsed().as_secs_f64(),
        rayon::current_num_threads()
    );
}
