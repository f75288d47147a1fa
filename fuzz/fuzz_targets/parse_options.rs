#![no_main]
//! Fuzzes the parsers of option values users type: `eat --target genus=…,boundaries=…`,
//! `--max-memory`, and `fit --offset` expressions evaluated on a grid of (u, v). No input
//! may panic (overflow checks are live under cargo fuzz); an accepted expression evaluates
//! to a finite number or an error, never NaN.

use libfuzzer_sys::fuzz_target;
use surfkit::fit::expr::Expr;
use surfkit::limits::MemoryBudget;
use surfkit::topology::TargetTopology;

fuzz_target!(|bytes: &[u8]| {
    let text = String::from_utf8_lossy(bytes);
    if let Ok(t) = TargetTopology::parse(&text) {
        let _ = t.euler_characteristic();
    }
    if let Ok(m) = MemoryBudget::parse(&text) {
        assert!(m.get() >= 1 << 20);
    }
    if let Ok(e) = Expr::parse(&text) {
        for (u, v) in [(0.0, 0.0), (0.5, -1.0), (1e300, 1e-300), (-3.0, 7.25)] {
            if let Ok(x) = e.eval(u, v) {
                assert!(x.is_finite(), "{text:?} at ({u}, {v}) gave {x}");
            }
        }
    }
});
