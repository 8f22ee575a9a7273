// Ctrl-C stops a running simulation.  YADE's O.run(n, True) waits in C++ (pyOmega::wait) without
// looking at Python's signal flag, so a SIGINT used to take effect only once the run had finished.
// When the plugin is loaded, a SIGINT handler is chained in front of the existing one (Python's):
// it wakes a watcher thread, which pauses the simulation loop; O.wait() then returns and Python
// raises its KeyboardInterrupt as usual.  The handler itself only writes one byte to a pipe
// (async-signal-safe).  Whoever sets a new handler later (IPython, in YADE's console, through
// Python's signal.signal) replaces ours: the watcher looks twice a second and chains in front of
// the new one (Python keeps its own view of its handlers, so signal.getsignal() is unaffected).
// SIGTERM gets the same chain: with its default action it still ends the process at once, but a
// script that handles it in Python (to save what it has, as examples/settling.py does) gets the
// loop paused first, so that its handler runs.
#include <core/Omega.hpp>
#include <algorithm>
#include <cerrno>
#include <iterator>
#include <poll.h>
#include <csignal>
#include <thread>
#include <unistd.h>

namespace yade {

namespace {
	int                     wakePipe[2] = { -1, -1 };
	constexpr int           watched[]   = { SIGINT, SIGTERM };
	struct sigaction        previousOf[std::size(watched)] {}; // the handler each watched signal had before ours

	void onInterrupt(int sig, siginfo_t* info, void* context)
	{
		const int  savedErrno = errno;
		const char byte       = 1;
		[[maybe_unused]] const ssize_t written = write(wakePipe[1], &byte, 1);
		errno                                  = savedErrno;
		const struct sigaction& previous       = previousOf[std::find(std::begin(watched), std::end(watched), sig) - std::begin(watched)];
		if (previous.sa_flags & SA_SIGINFO) {
			if (previous.sa_sigaction) previous.sa_sigaction(sig, info, context);
		} else if (previous.sa_handler == SIG_DFL) {
			signal(sig, SIG_DFL); // nobody handled it before us: keep its default action
			raise(sig);
		} else if (previous.sa_handler != SIG_IGN) {
			previous.sa_handler(sig);
		}
	}

	// Chains onInterrupt in front of the current handler of watched[k], unless it is there already or
	// the signal is ignored on purpose (e.g. SIGINT of a background job).
	void chain(size_t k)
	{
		struct sigaction current {};
		if (sigaction(watched[k], nullptr, &current) != 0) return;
		if ((current.sa_flags & SA_SIGINFO) && current.sa_sigaction == onInterrupt) return;
		if (!(current.sa_flags & SA_SIGINFO) && current.sa_handler == SIG_IGN) return;
		previousOf[k] = current;
		struct sigaction mine {};
		mine.sa_sigaction = onInterrupt;
		mine.sa_flags     = SA_SIGINFO | SA_RESTART;
		sigemptyset(&mine.sa_mask);
		sigaction(watched[k], &mine, nullptr);
	}
	void chain()
	{
		for (size_t k = 0; k < std::size(watched); ++k)
			chain(k);
	}

	void watch()
	{
		pollfd wake { wakePipe[0], POLLIN, 0 };
		while (true) {
			const int ready = poll(&wake, 1, 500);
			if (ready < 0 && errno != EINTR) return;
			if (ready <= 0) { // nothing: make sure the handler is still ours
				chain();
				continue;
			}
			char byte;
			if (read(wakePipe[0], &byte, 1) <= 0) return;
			if (Omega::instance().isRunning()) Omega::instance().pause();
		}
	}

	struct InterruptWatcher {
		InterruptWatcher()
		{
			if (pipe(wakePipe) != 0) return;
			chain();
			std::thread(watch).detach();
		}
	} installed;
}

} // namespace yade
