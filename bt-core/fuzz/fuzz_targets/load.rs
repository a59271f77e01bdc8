//! `load` on arbitrary bytes must never panic; whatever loads must tick and halt
//! without panicking either.
#![no_main]

use bt_core::script::{ScriptFault, Value};
use bt_core::{
    BehaviorInfo, BehaviorSet, Context, Executor, Leaf, Node, NodeId, NodeState, Selection, Status, Tree, fingerprint,
    image,
};
use libfuzzer_sys::fuzz_target;

const SET: [BehaviorInfo<'static>; 5] = [
    BehaviorInfo::condition("c0?", 0),
    BehaviorInfo::condition("c1?", 1),
    BehaviorInfo::action("a0!", 0),
    BehaviorInfo::action("a1!", 2),
    BehaviorInfo::action("a4!", 4), // extended leaves: values in the image's value table
];

/// Leaf outcomes drawn from the input's own bytes, so ticking explores the tree.
struct Bytes<'a>(&'a [u8], usize);

impl Bytes<'_> {
    fn next(&mut self) -> u8 {
        let b = self.0.get(self.1 % self.0.len().max(1)).copied().unwrap_or(0);
        self.1 += 1;
        b
    }
}

impl BehaviorSet for Bytes<'_> {
    fn condition(&mut self, _: &Leaf, _: Context<'_>) -> Status {
        [Status::Success, Status::Failure, Status::Success, Status::Skipped][usize::from(self.next() % 4)]
    }
    // Actions and gates: any status, Skipped included.
    fn action(&mut self, leaf: &Leaf, ctx: Context<'_>) -> Status {
        // Read every value, as a behavior would.
        self.1 += ctx.args(leaf).iter().map(|&v| usize::from(v) & 1).sum::<usize>();
        [Status::Success, Status::Failure, Status::Running, Status::Running, Status::Skipped][usize::from(self.next() % 5)]
    }
    fn halt(&mut self, _: &Leaf, _: NodeId) {}
    // Scripts (script nodes, guards' hooks, preconditions, literal loops' elements) and
    // pops of blackboard queues answer from the bytes too, so the paths after them are
    // explored; now and then they fault, as a script can.
    fn script(&mut self, code: &[u16], _: Context<'_>) -> Result<Value, ScriptFault> {
        self.1 += code.len() & 1;
        match self.next() % 5 {
            0 => Err(ScriptFault::NotPermitted),
            b => Ok(Value::Bool(b & 1 == 1)),
        }
    }
    fn pop(&mut self, queue: u16, value: u16, _: Context<'_>) -> Result<bool, ScriptFault> {
        self.1 += usize::from(queue ^ value) & 1;
        match self.next() % 5 {
            0 => Err(ScriptFault::Unset { slot: queue }),
            b => Ok(b & 1 == 1),
        }
    }
    // ManualSelectors are told a child or a status from the bytes too: mostly a child
    // they have, now and then one past the last (a fault), now and then a refusal.
    fn select(&mut self, children: u8, _: Context<'_>) -> Result<Selection, ScriptFault> {
        Ok(match self.next() % 8 {
            0 => return Err(ScriptFault::NoSelections),
            1 => Selection::Success,
            2 => Selection::Failure,
            3 => Selection::Running,
            _ => Selection::Child(self.next() % children.saturating_add(1)),
        })
    }
}

fuzz_target!(|data: &[u8]| {
    // Half the inputs as they come; the other half sealed with a valid envelope so the
    // fuzzer reaches the node decoder and the validator instead of the CRC check.
    let mut sealed;
    let bytes = if data.first().is_some_and(|b| b & 1 == 1) && data.len() > 2 {
        sealed = Vec::with_capacity(data.len() + 20);
        sealed.extend_from_slice(&image::MAGIC);
        sealed.extend_from_slice(&image::VERSION.to_le_bytes());
        sealed.extend_from_slice(&fingerprint(&SET).to_le_bytes());
        sealed.extend_from_slice(&u16::from(data[1] % 40).to_le_bytes());
        sealed.extend_from_slice(&data[2..]);
        let crc = image::crc32(&sealed);
        sealed.extend_from_slice(&crc.to_le_bytes());
        &sealed[..]
    } else {
        data
    };
    let mut storage = [Node::EMPTY; 48];
    let mut values = [0u16; 64];
    let Ok(tree): Result<Tree<'_, 12>, _> = bt_core::load_with(bytes, &SET, &mut storage, &mut values) else {
        return;
    };
    let mut state = [NodeState::IDLE; 48];
    let mut exec = Executor::new(tree, &mut state).expect("state fits");
    let mut world = Bytes(data, 0);
    // The clock moves by input bytes, so that clocked kinds expire; a woken tree is
    // ticked again a few times, as BehaviorTree.CPP's tickOnce() would.
    let mut now = 0u32;
    for _ in 0..6 {
        now = now.wrapping_add(u32::from(world.next()));
        let mut again = 0;
        while exec.tick(&mut world, now) == Ok(Status::Running) && exec.take_woken() && again < 4 {
            again += 1;
        }
    }
    exec.halt_all(&mut world);
});
