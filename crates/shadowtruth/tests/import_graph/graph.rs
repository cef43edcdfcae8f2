//! The file graph of one crate: its circles (strongly connected files), its floors (the longest
//! chain of imports below each file) and the arrows that point back up.

use std::collections::BTreeSet;

use crate::resolve::Arrows;

pub struct FileGraph {
    pub files: Vec<String>,
    /// `successors[i]`: the files file `i` imports.
    pub successors: Vec<BTreeSet<usize>>,
}

impl FileGraph {
    pub fn new(files: &BTreeSet<String>, arrows: &Arrows) -> FileGraph {
        let files: Vec<String> = files.iter().cloned().collect();
        let index = |file: &String| files.binary_search(file).ok();
        let mut successors = vec![BTreeSet::new(); files.len()];
        for (from, to) in arrows.keys() {
            if let (Some(from), Some(to)) = (index(from), index(to)) {
                successors[from].insert(to);
            }
        }
        FileGraph { files, successors }
    }

    /// Strongly connected components (Tarjan), each sorted, in order of their first file.
    pub fn components(&self) -> Vec<Vec<usize>> {
        let mut tarjan = Tarjan::new(self.files.len());
        for file in 0..self.files.len() {
            if tarjan.order[file].is_none() {
                tarjan.visit(self, file);
            }
        }
        let mut components = tarjan.components;
        components.iter_mut().for_each(|c| c.sort());
        components.sort();
        components
    }

    /// Components of more than one file: files that import each other through some chain.
    pub fn circles(&self) -> Vec<Vec<usize>> {
        self.components().into_iter().filter(|c| c.len() > 1).collect()
    }

    /// Longest-path layering: a file that imports nothing of its crate is on floor 0, any other
    /// one floor above the highest file it imports; files of one circle share a floor.
    pub fn floors(&self) -> Vec<usize> {
        let components = self.components();
        let mut component_of = vec![0; self.files.len()];
        for (c, files) in components.iter().enumerate() {
            files.iter().for_each(|&f| component_of[f] = c);
        }
        let mut floor_of_component: Vec<Option<usize>> = vec![None; components.len()];
        for c in 0..components.len() {
            component_floor(self, &components, &component_of, c, &mut floor_of_component);
        }
        (0..self.files.len()).map(|f| floor_of_component[component_of[f]].unwrap_or(0)).collect()
    }

    /// Arrows to a file still open on a depth-first walk in file order: removing them leaves
    /// no circle.
    pub fn back_arrows(&self) -> Vec<(usize, usize)> {
        let mut state = vec![0u8; self.files.len()];
        let mut back = Vec::new();
        for file in 0..self.files.len() {
            if state[file] == 0 {
                self.walk(file, &mut state, &mut back);
            }
        }
        back
    }

    fn walk(&self, file: usize, state: &mut [u8], back: &mut Vec<(usize, usize)>) {
        state[file] = 1;
        for &next in &self.successors[file] {
            match state[next] {
                0 => self.walk(next, state, back),
                1 => back.push((file, next)),
                _ => {}
            }
        }
        state[file] = 2;
    }
}

fn component_floor(
    graph: &FileGraph,
    components: &[Vec<usize>],
    component_of: &[usize],
    c: usize,
    floors: &mut Vec<Option<usize>>,
) -> usize {
    if let Some(floor) = floors[c] {
        return floor;
    }
    let below: BTreeSet<usize> = components[c]
        .iter()
        .flat_map(|&f| graph.successors[f].iter().map(|&s| component_of[s]))
        .filter(|&s| s != c)
        .collect();
    let floor =
        below.into_iter().map(|s| component_floor(graph, components, component_of, s, floors) + 1).max();
    floors[c] = Some(floor.unwrap_or(0));
    floors[c].unwrap()
}

struct Tarjan {
    order: Vec<Option<usize>>,
    low: Vec<usize>,
    on_stack: Vec<bool>,
    stack: Vec<usize>,
    next_order: usize,
    components: Vec<Vec<usize>>,
}

impl Tarjan {
    fn new(count: usize) -> Tarjan {
        Tarjan {
            order: vec![None; count],
            low: vec![0; count],
            on_stack: vec![false; count],
            stack: Vec::new(),
            next_order: 0,
            components: Vec::new(),
        }
    }

    fn visit(&mut self, graph: &FileGraph, file: usize) {
        self.order[file] = Some(self.next_order);
        self.low[file] = self.next_order;
        self.next_order += 1;
        self.stack.push(file);
        self.on_stack[file] = true;
        for &next in &graph.successors[file] {
            match self.order[next] {
                None => {
                    self.visit(graph, next);
                    self.low[file] = self.low[file].min(self.low[next]);
                }
                Some(order) if self.on_stack[next] => self.low[file] = self.low[file].min(order),
                Some(_) => {}
            }
        }
        if Some(self.low[file]) == self.order[file] {
            let mut component = Vec::new();
            while let Some(top) = self.stack.pop() {
                self.on_stack[top] = false;
                component.push(top);
                if top == file {
                    break;
                }
            }
            self.components.push(component);
        }
    }
}
