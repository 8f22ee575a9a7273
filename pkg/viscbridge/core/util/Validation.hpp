// Range checks for user parameters: every failure names the parameter, its value and the allowed
// range (std::invalid_argument, a ValueError in Python).
#pragma once
#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace viscbridge {

inline std::string formatValue(double v)
{
	std::ostringstream o;
	o.precision(10);
	o << v;
	return o.str();
}

[[noreturn]] inline void rejectValue(const std::string& owner, const std::string& parameter, double value, const std::string& allowed)
{
	throw std::invalid_argument(owner + "." + parameter + "=" + formatValue(value) + " is out of range; allowed: " + allowed + ".");
}

inline void requireFinite(const std::string& owner, const std::string& parameter, double v, const std::string& allowed)
{
	if (!std::isfinite(v)) rejectValue(owner, parameter, v, allowed);
}
inline void requirePositive(const std::string& owner, const std::string& parameter, double v)
{
	if (!(v > 0) || !std::isfinite(v)) rejectValue(owner, parameter, v, "> 0 (finite)");
}
inline void requireNonNegative(const std::string& owner, const std::string& parameter, double v, const std::string& meaningOfZero = "")
{
	if (!(v >= 0) || !std::isfinite(v)) rejectValue(owner, parameter, v, ">= 0 (finite)" + meaningOfZero);
}
inline void requireInRange(const std::string& owner, const std::string& parameter, double v, double lo, bool loOpen, double hi, bool hiOpen)
{
	const bool okLo = loOpen ? v > lo : v >= lo;
	const bool okHi = hiOpen ? v < hi : v <= hi;
	if (!(okLo && okHi) || !std::isfinite(v))
		rejectValue(owner, parameter, v, std::string(loOpen ? "(" : "[") + formatValue(lo) + ", " + formatValue(hi) + (hiOpen ? ")" : "]"));
}

// Index of `value` in `names`; otherwise std::invalid_argument naming the parameter and the allowed
// values (YADE turns it into a Python ValueError).
template <std::size_t N>
std::size_t parseName(const std::string& owner, const std::string& parameter, const std::string& value, const std::array<const char*, N>& names,
                      const char* what = "model")
{
	std::string allowed;
	for (std::size_t i = 0; i < N; ++i) {
		if (value == names[i]) return i;
		allowed += std::string(i ? ", '" : "'") + names[i] + "'";
	}
	throw std::invalid_argument(owner + "." + parameter + "='" + value + "' is not a known " + what + "; allowed: " + allowed + ".");
}

} // namespace viscbridge
