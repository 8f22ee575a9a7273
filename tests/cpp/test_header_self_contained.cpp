// The kernel headers must compile and link on their own (plain C++17 + Eigen, no YADE).  This file
// includes nothing but one kernel header and GoogleTest, and calls code that uses Vec3::cross.
// Eigen declares cross() in <Eigen/Core> but defines it in <Eigen/Geometry>; a header that forgets
// the latter compiles but fails to link (undefined reference to MatrixBase::cross) — as the
// committed Vector.hpp of cd125ca did.
#include "viscbridge/core/pair/PairKernel.hpp"
#include <gtest/gtest.h>

TEST(KernelHeaders, PairKernelBringsInEigenGeometry)
{
#ifdef EIGEN_GEOMETRY_MODULE_H
	constexpr bool geometryIncluded = true;
#else
	constexpr bool geometryIncluded = false;
#endif
	EXPECT_TRUE(geometryIncluded) << "Vector.hpp must #include <Eigen/Geometry> (cross products)";
	// And the cross product actually works from here: e_x × e_y = e_z, through a kernel function.
	const viscbridge::SlipTangential model(1.0, 1e-3);
	const auto r = model.evaluate({ viscbridge::Vec3::UnitY(), viscbridge::Vec3::Zero(), viscbridge::Vec3::UnitX(), viscbridge::Vec3::Zero(), 1e-3, 1e-3, 0.0, 1e-6 });
	// slip = (r + S/2) ω1 × n = 1e-3 e_x × e_y = 1e-3 e_z; F = −C_T slip points along −e_z.
	EXPECT_LT(r.force1.z(), 0.0);
	EXPECT_NEAR(r.force1.x(), 0.0, 1e-20);
}
