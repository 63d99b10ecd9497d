// A rigid transform T_ab in SE(3), stored as a unit quaternion and a
// translation: p_a = T_ab * p_b = q_ab * p_b + t_ab.
//
//   (T_ab * T_bc).q = q_ab q_bc,  (T_ab * T_bc).t = q_ab t_bc + t_ab
//   T_ab^-1 = (q_ab^*, -(q_ab^* t_ab))
//
// Templated on the scalar so ceres::Jet flows through; Cast<U>() converts.
#ifndef SYMBA_GEOMETRY_RIGID3_H_
#define SYMBA_GEOMETRY_RIGID3_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace symba {

template <typename T>
struct Rigid3 {
  using Quaternion = Eigen::Quaternion<T>;
  using Vector = Eigen::Matrix<T, 3, 1>;

  Quaternion q = Quaternion::Identity();
  Vector t = Vector::Zero();

  Rigid3() = default;
  Rigid3(const Quaternion& rotation, const Vector& translation)
      : q(rotation), t(translation) {}

  static Rigid3 Identity() { return Rigid3(); }

  Rigid3 Inverse() const {
    const Quaternion q_inv = q.conjugate();
    return Rigid3(q_inv, -(q_inv * t));
  }

  Rigid3 operator*(const Rigid3& other) const {
    return Rigid3(q * other.q, q * other.t + t);
  }

  Vector operator*(const Vector& p) const { return q * p + t; }

  Eigen::Matrix<T, 3, 3> RotationMatrix() const { return q.toRotationMatrix(); }

  template <typename U>
  Rigid3<U> Cast() const {
    return Rigid3<U>(q.template cast<U>(), t.template cast<U>());
  }
};

using Rigid3d = Rigid3<double>;

}  // namespace symba

#endif  // SYMBA_GEOMETRY_RIGID3_H_
