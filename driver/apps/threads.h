#pragma once

/// How the driver's threads share the cores with other processes.
namespace softpack::apps
{

/// Make OpenMP threads wait passively (sleep) instead of spinning.
///
/// libgomp reads OMP_WAIT_POLICY once, when the program is loaded, and by
/// default spins at every barrier before it sleeps. A time step runs a dozen
/// short parallel regions; when another process holds a core, the spinning
/// thread burns the time slice its partner needs to reach the barrier, and
/// the run slows down by an order of magnitude (issue 18: 62 s instead of
/// 10 s for 600 steps of 26 disks on a loaded machine). Sleeping costs a
/// futex wake-up per region, microseconds against a step's milliseconds.
///
/// If OMP_WAIT_POLICY is unset, set it to PASSIVE and re-execute the program
/// with the same arguments (before MPI_Init: the process keeps its PID and
/// environment). A value the user set is kept. If the re-execution fails the
/// run goes on, spinning, with a warning.
/// @param[in] argv The program's arguments, argv[argc] == nullptr
void ensure_passive_waiting(char** argv);

/// Use this many OpenMP threads (0: OpenMP's default, the cores this process
/// may run on).
/// @throws std::invalid_argument if threads < 0
void set_thread_count(int threads);

} // namespace softpack::apps
