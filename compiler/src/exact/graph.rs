//! The decomposition (transition) graph of k-words (\[N\] §2.2.2, \[G\] Figs. A.8–A.9).
//!
//! F_0 is the set of k-factors of ω ω ω … (the axiom labels every initial interval); F_{s+1} is
//! the set of k-factors of π(u), u ∈ F_s (every k-factor of π(W) lies in π of a k-factor of W
//! since no rule is empty). The graph has an edge u → v when v is a k-factor of π(u). A word is
//! *recurring* when it is reachable from a cycle (then it lies in F_s for infinitely many s);
//! the others are *transitional*: they form a DAG, so they appear only in the first steps.

use crate::exact::lsystem::{LSystem, Word};
use crate::exact::work;
use petgraph::algo::tarjan_scc;
use petgraph::graph::{DiGraph, NodeIndex};
use std::collections::{BTreeSet, HashMap};

/// One reachable k-word.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WordInfo {
    /// The word.
    pub word: Word,
    /// The first s with the word in F_s (the paper's "(s+1)-th step").
    pub first_step: usize,
    /// Appears only in finitely many F_s.
    pub transitional: bool,
    /// For transitional words, every s with the word in F_s.
    pub steps: Vec<usize>,
}

/// All k-words reachable from the axiom with their transitions.
#[derive(Clone, Debug)]
pub struct Reach {
    /// Word length k (d+1 for masks, 2d+1 for certificates).
    pub k: usize,
    /// Words sorted by first step, then symbol order.
    pub words: Vec<WordInfo>,
    /// Index of each word in `words`.
    pub index: HashMap<Word, usize>,
    /// Successors (distinct k-factors of π(w)) of each word, by index.
    pub edges: Vec<Vec<usize>>,
    /// Strongly connected components with a cycle (size > 1 or a self-loop), by index.
    pub sccs: Vec<Vec<usize>>,
}

/// The distinct k-factors of `w`, in order of first occurrence.
fn factors(w: &[u8], k: usize) -> Vec<Word> {
    let mut seen = BTreeSet::new();
    let mut out = Vec::new();
    for f in w.windows(k) {
        if seen.insert(f.to_vec()) {
            out.push(f.to_vec());
        }
    }
    out
}

/// F_0: the k-factors of ω repeated.
fn initial(ls: &LSystem, k: usize) -> Vec<Word> {
    let reps = k.div_ceil(ls.axiom.len()) + 1;
    let periodic: Word = ls
        .axiom
        .iter()
        .copied()
        .cycle()
        .take(reps * ls.axiom.len())
        .collect();
    factors(&periodic[..ls.axiom.len() + k - 1], k)
}

/// Computes the k-words reachable from the axiom, the graph, its cycles and transitional steps.
pub fn reach(ls: &LSystem, k: usize) -> Reach {
    reach_from(ls, k, initial(ls, k))
}

/// As [`reach`], from the given initial k-words (F_0) instead of the axiom's.
pub fn reach_from(ls: &LSystem, k: usize, start: Vec<Word>) -> Reach {
    // Breadth-first closure: the BFS depth of a word is its first step.
    let mut words: Vec<Word> = Vec::new();
    let mut first: Vec<usize> = Vec::new();
    let mut index: HashMap<Word, usize> = HashMap::new();
    for w in start {
        if index.contains_key(&w) {
            continue;
        }
        index.insert(w.clone(), words.len());
        words.push(w);
        first.push(0);
    }
    let mut succ: Vec<Vec<usize>> = Vec::new();
    let mut i = 0;
    while i < words.len() {
        let mut out = Vec::new();
        let image = ls.rewrite(&words[i]);
        // Hashing the |π(w)| factors of length k: about k·|π(w)|/8 units (exact::work).
        work::charge(1 + (k * image.len()) as u64 / 8);
        for f in factors(&image, k) {
            let j = *index.entry(f.clone()).or_insert_with(|| {
                words.push(f);
                first.push(first[i] + 1);
                words.len() - 1
            });
            out.push(j);
        }
        succ.push(out);
        i += 1;
    }

    let mut g = DiGraph::<usize, ()>::new();
    let nodes: Vec<NodeIndex> = (0..words.len()).map(|i| g.add_node(i)).collect();
    for (i, out) in succ.iter().enumerate() {
        for &j in out {
            g.add_edge(nodes[i], nodes[j], ());
        }
    }
    let sccs: Vec<Vec<usize>> = tarjan_scc(&g)
        .into_iter()
        .map(|c| c.into_iter().map(|v| g[v]).collect::<Vec<_>>())
        .filter(|c: &Vec<usize>| c.len() > 1 || succ[c[0]].contains(&c[0]))
        .collect();
    let mut recurring = vec![false; words.len()];
    let mut stack: Vec<usize> = sccs.iter().flatten().copied().collect();
    while let Some(v) = stack.pop() {
        if !recurring[v] {
            recurring[v] = true;
            stack.extend(&succ[v]);
        }
    }

    // Steps of transitional words: a transitional word in F_s has a chain of s transitional
    // predecessors, so F_s holds none once s exceeds their number.
    let mut steps: Vec<Vec<usize>> = vec![Vec::new(); words.len()];
    let mut level: BTreeSet<usize> = (0..words.len()).filter(|&i| first[i] == 0).collect();
    let transitional_count = recurring.iter().filter(|r| !**r).count();
    for s in 0..=transitional_count {
        work::charge(1 + level.len() as u64);
        for &v in &level {
            if !recurring[v] {
                steps[v].push(s);
            }
        }
        level = level
            .iter()
            .flat_map(|&v| succ[v].iter().copied())
            .collect();
    }

    // Renumber: by first step, then symbols.
    let mut order: Vec<usize> = (0..words.len()).collect();
    order.sort_by(|&a, &b| (first[a], &words[a]).cmp(&(first[b], &words[b])));
    let mut renum = vec![0; words.len()];
    for (new, &old) in order.iter().enumerate() {
        renum[old] = new;
    }
    let infos: Vec<WordInfo> = order
        .iter()
        .map(|&o| WordInfo {
            word: words[o].clone(),
            first_step: first[o],
            transitional: !recurring[o],
            steps: steps[o].clone(),
        })
        .collect();
    let edges = order
        .iter()
        .map(|&o| succ[o].iter().map(|&j| renum[j]).collect())
        .collect();
    let mut sccs: Vec<Vec<usize>> = sccs
        .into_iter()
        .map(|c| {
            let mut c: Vec<usize> = c.into_iter().map(|v| renum[v]).collect();
            c.sort_unstable();
            c
        })
        .collect();
    sccs.sort();
    let index = infos
        .iter()
        .enumerate()
        .map(|(i, w)| (w.word.clone(), i))
        .collect();
    Reach {
        k,
        words: infos,
        index,
        edges,
        sccs,
    }
}
