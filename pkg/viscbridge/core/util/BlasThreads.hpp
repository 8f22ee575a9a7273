// The number of threads the BLAS under CHOLMOD runs on.  Debian's default BLAS is OpenBLAS built
// with its own pthreads pool, sized when the process starts from OMP_NUM_THREADS (YADE's -j), beside
// OpenMP's pool: after each call its workers spin for a while before they sleep, and on a machine
// with as many cores as threads they take the cores YADE's OpenMP loops need next.  Measured on two
// cores, a 10⁴-sphere bed's implicit step took 0.53× on two threads with OpenBLAS's pool busy and
// 0.98× with OpenBLAS on one thread (docs/performance.md §3).  YADE-free.
//
//   setBlasThreads(n)   OpenBLAS's threads for the calls that follow (only when it changes);
//                       false if the process's BLAS is not OpenBLAS (then nothing to set)
//   blasThreads()       OpenBLAS's current count; 0 if it is not OpenBLAS
#pragma once
#include <dlfcn.h>

namespace viscbridge {

namespace detail {
	// OpenBLAS's own controls, found in the process (RTLD_NOLOAD: never loaded here) rather than linked,
	// so that another BLAS behind libblas.so.3 (reference BLAS, BLIS) leaves this a no-op.
	struct OpenBlasControls {
		void (*set)(int) = nullptr;
		int (*get)()     = nullptr;
		OpenBlasControls()
		{
			void* lib = dlopen("libopenblas.so.0", RTLD_LAZY | RTLD_NOLOAD);
			if (!lib) return;
			set = reinterpret_cast<void (*)(int)>(dlsym(lib, "openblas_set_num_threads"));
			get = reinterpret_cast<int (*)()>(dlsym(lib, "openblas_get_num_threads"));
			if (!set || !get) set = nullptr, get = nullptr;
		}
	};
	inline const OpenBlasControls& openBlas()
	{
		static const OpenBlasControls controls;
		return controls;
	}
} // namespace detail

inline int blasThreads() { return detail::openBlas().get ? detail::openBlas().get() : 0; }

inline bool setBlasThreads(int n)
{
	const detail::OpenBlasControls& blas = detail::openBlas();
	if (!blas.set) return false;
	if (blas.get() != n) blas.set(n); // setting takes OpenBLAS's server lock: not on every solve
	return true;
}

} // namespace viscbridge
