//! The script machine: never a panic on any words, what `check` accepts runs, and a counter
//! as a controller runs it.
#![allow(clippy::unwrap_used, clippy::indexing_slicing)]

use bt_core::PortTable;
use bt_core::script::{Value, check, op, run, truth};
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]
    #[test]
    fn any_words_check_and_run_without_panicking(code in prop::collection::vec(0u16..30, 0..40)) {
        let ports = PortTable::EMPTY;
        let checked = check(&code, &ports);
        let ran = run(&code, &ports, &mut [None; 4]);
        // What the loader accepts never fails as malformed when it runs.
        if checked.is_ok() {
            prop_assert!(!matches!(ran, Err(bt_core::script::ScriptFault::Malformed { .. })), "{code:?}: {ran:?}");
        }
    }
}

#[test]
fn a_counter_counts_and_its_condition_holds_until_three() {
    // `n := 0` once, then `n += 1; n < 3` per tick.
    let one = 1.0f64.to_bits();
    let w = |b: u64| [b as u16, (b >> 16) as u16, (b >> 32) as u16, (b >> 48) as u16];
    let three = w(3.0f64.to_bits());
    let o = w(one);
    let count = [
        op::DOUBLE,
        o[0],
        o[1],
        o[2],
        o[3],
        op::STORE,
        2,
        0,
        0,
        op::POP,
        op::LOAD,
        0,
        op::DOUBLE,
        three[0],
        three[1],
        three[2],
        three[3],
        op::CMP,
        2,
    ];
    let mut bb = [Some(Value::Int(0))];
    let held: Vec<bool> = (0..4).map(|_| truth(run(&count, &PortTable::EMPTY, &mut bb).unwrap()).unwrap()).collect();
    assert_eq!(held, [true, true, false, false]);
    assert_eq!(bb[0], Some(Value::Int(4)));
}
