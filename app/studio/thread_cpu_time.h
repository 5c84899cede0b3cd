// SPDX-License-Identifier: MIT
#pragma once
/// @file thread_cpu_time.h
/// CPU time of the calling thread, for the view's render timing: the time one frame costs the
/// GUI thread, not the wall clock (which also counts waiting for the GPU and other processes);
/// and the process's minor page faults, for where a step's fresh memory went. Kept apart so that the platform headers it needs (<windows.h>) stay out of the view's code.

namespace deepcut::studio {

/// CPU time the calling thread has used, in ms, from an arbitrary origin (compare two calls):
/// the thread CPU clock (clock_gettime(CLOCK_THREAD_CPUTIME_ID), ns resolution) where <ctime>
/// defines it; on Windows the thread's kernel and user times (GetThreadTimes), which advance
/// only at the scheduler's tick (about 15.6 ms by default): a frame's time there is 0 or a
/// tick, meaningful only averaged over many frames. Elsewhere, or when the clock fails, the
/// process's CPU time (std::clock), which also counts other threads (the renderer's).
double thread_cpu_ms();

/// Minor page faults the whole process has taken (getrusage's ru_minflt), from an arbitrary
/// origin (compare two calls): each is a page of fresh memory touched for the first time, which
/// costs time that instruction counts do not show. 0 where the platform does not count them.
long process_minor_faults();

}  // namespace deepcut::studio
