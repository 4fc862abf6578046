//! Instruction counts from SysTick under QEMU's `-icount shift=0`.
//!
//! With `-icount shift=0` QEMU advances its virtual clock by one
//! nanosecond per executed instruction; SysTick counts the mps2 board's
//! 25 MHz processor clock in virtual time, so one tick is 40 instructions
//! (the figures are exact to one tick). The 24-bit counter wraps every
//! 2^24 ticks; the exception handler counts the wraps.

use core::sync::atomic::{AtomicU32, Ordering};
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m::peripheral::SYST;
use cortex_m_rt::exception;

const RELOAD: u32 = 0x00FF_FFFF;
/// Instructions per SysTick tick (1 ns per instruction, 40 ns per tick).
const INS_PER_TICK: u64 = 40;

static WRAPS: AtomicU32 = AtomicU32::new(0);

#[exception]
fn SysTick() {
    WRAPS.fetch_add(1, Ordering::Relaxed);
}

/// Starts the counter (processor clock, interrupt on every wrap).
pub fn start(mut syst: SYST) {
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(RELOAD);
    syst.clear_current();
    syst.enable_interrupt();
    syst.enable_counter();
}

/// Instructions executed since [`start`] (to one tick).
pub fn instructions() -> u64 {
    loop {
        let w0 = WRAPS.load(Ordering::Relaxed);
        let cur = SYST::get_current();
        let w1 = WRAPS.load(Ordering::Relaxed);
        if w0 == w1 {
            let ticks = w0 as u64 * (RELOAD as u64 + 1) + (RELOAD - cur) as u64;
            return ticks * INS_PER_TICK;
        }
    }
}
