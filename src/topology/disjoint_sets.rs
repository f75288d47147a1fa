//! Disjoint sets (union–find with path halving and union by index), for components,
//! fans and boundary loops.

#[derive(Debug, Clone)]
pub struct DisjointSets {
    parent: Vec<u32>,
}

impl DisjointSets {
    pub fn new(n: usize) -> Self {
        DisjointSets {
            parent: (0..n as u32).collect(),
        }
    }

    pub fn find(&mut self, mut i: u32) -> u32 {
        while self.parent[i as usize] != i {
            let grand = self.parent[self.parent[i as usize] as usize];
            self.parent[i as usize] = grand;
            i = grand;
        }
        i
    }

    /// The root of every element, reusing the parent array.
    pub fn into_roots(mut self) -> Vec<u32> {
        for i in 0..self.parent.len() as u32 {
            let r = self.find(i);
            self.parent[i as usize] = r;
        }
        self.parent
    }

    /// Joins the sets of `a` and `b` (the smaller root becomes the root).
    pub fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.parent[ra.max(rb) as usize] = ra.min(rb);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn joins() {
        let mut d = DisjointSets::new(5);
        d.union(0, 3);
        d.union(3, 4);
        assert_eq!(d.find(4), 0);
        assert_ne!(d.find(1), d.find(2));
    }
}
