// SPDX-License-Identifier: MIT
#pragma once
/// @file thread_cpu_time.h
/// CPU time of the calling thread, for the view's render timing: the time one frame costs the
/// GUI thread, not the wall clock (which also counts waiting for the GPU and other processes).
/// Kept apart so that the platform headers it needs (<windows.h>) stay out of the view's code.

namespace deepcut::studio {

/// CPU time the calling thread has used, in ms, from an arbitrary origin (compare two calls):
/// the thread CPU clock (clock_gettime(CLOCK_THREAD_CPUTIME_ID), ns resolution) where <ctime>
/// defines it; on Windows the thread's kernel and user times (GetThreadTimes), which advance
/// only at the scheduler's tick (about 15.6 ms by default): a frame's time there is 0 or a
/// tick, meaningful only averaged over many frames. Elsewhere, or when the clock fails, the
/// process's CPU time (std::clock), which also counts other threads (the renderer's).
double thread_cpu_ms();

}  // namespace deepcut::studio
