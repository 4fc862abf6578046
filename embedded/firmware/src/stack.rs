//! Stack painting: fill the unused stack with a pattern, later find the
//! deepest word that no longer holds it.
//!
//! cortex-m-rt puts the stack at the top of RAM, growing down towards
//! `__sheap` (the end of `.bss`); everything between is free.

use core::ptr::{addr_of, read_volatile, write_volatile};

const PAINT: u32 = 0xC5C5_5C5C;
/// Bytes below the current stack pointer left alone by [`paint`] (its own
/// frame and that of its caller's callees).
const MARGIN: usize = 256;

extern "C" {
    static __sheap: u32;
    static _stack_start: u32;
}

fn bottom() -> usize {
    // SAFETY: only the address of the linker symbol is taken.
    addr_of!(__sheap) as usize
}

fn top() -> usize {
    // SAFETY: as above.
    addr_of!(_stack_start) as usize
}

/// Paints the free stack below the current stack pointer.
#[inline(never)]
pub fn paint() {
    let sp = cortex_m::register::msp::read() as usize;
    let end = (sp - MARGIN) & !3;
    let mut a = (bottom() + 3) & !3;
    while a < end {
        // SAFETY: [bottom, sp - MARGIN) is free RAM between .bss and the
        // live stack; nothing else uses it.
        unsafe { write_volatile(a as *mut u32, PAINT) };
        a += 4;
    }
}

/// Bytes of stack used at the deepest point since the last [`paint`]
/// (from the top of RAM).
#[inline(never)]
pub fn high_water() -> usize {
    let mut a = (bottom() + 3) & !3;
    let t = top();
    while a < t {
        // SAFETY: reads of RAM between .bss and the top of the stack.
        if unsafe { read_volatile(a as *const u32) } != PAINT {
            break;
        }
        a += 4;
    }
    t - a
}
