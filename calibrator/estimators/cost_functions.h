// The calibrator's Ceres cost functions, in one place (as COLMAP's estimators/cost_functions.h):
// the angular epipolar error of the two-view refinement, the relative-rotation error of rotation
// averaging and the reprojection error of the multi-frame rig bundle adjustment.
//
// Internal to the calibrator: included by its own sources and tests only, so that Ceres stays a
// private dependency of the library (no Ceres type in its public headers).
//
// Quaternions are Eigen's coefficient order (x, y, z, w), as ceres::EigenQuaternionManifold.
#pragma once

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <ceres/autodiff_cost_function.h>
#include <ceres/cost_function.h>
#include <ceres/problem.h>
#include <ceres/rotation.h>
#include <ceres/sized_cost_function.h>

#include "geometry/camera.h"
#include "geometry/camera_models.h"
#include "geometry/pose_interpolation.h"

namespace rigsim {

// Angular epipolar residual of one correspondence (two_view.h EpipolarAngularResidual): sines of
// the angles between bearing b and the epipolar plane of bearing a (in B), and between bearing a
// and the epipolar plane of bearing b (in A). Parameters: the rotation (4) and the unit
// translation (3) of cam_b_from_cam_a. The bearings already went through their cameras' models.
struct EpipolarAngularCost {
  EpipolarAngularCost(const Eigen::Vector3d& fa, const Eigen::Vector3d& fb) : fa_(fa), fb_(fb) {}

  template <typename T>
  bool operator()(const T* q, const T* t, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> rot(q);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> tr(t);
    const Eigen::Matrix<T, 3, 1> fa = fa_.cast<T>();
    const Eigen::Matrix<T, 3, 1> fb = fb_.cast<T>();
    // Normal of the epipolar plane through bearing a, in B; and through bearing b, in A.
    const Eigen::Matrix<T, 3, 1> nb = tr.cross(rot * fa);
    const Eigen::Matrix<T, 3, 1> na = rot.conjugate() * tr.cross(fb);
    // The tiny constant keeps the derivative finite when a bearing points at the epipole.
    residual[0] = nb.dot(fb) / sqrt(nb.squaredNorm() + T(1e-20));
    residual[1] = na.dot(fa) / sqrt(na.squaredNorm() + T(1e-20));
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& fa, const Eigen::Vector3d& fb) {
    return new ceres::AutoDiffCostFunction<EpipolarAngularCost, 2, 4, 3>(new EpipolarAngularCost(fa, fb));
  }

  Eigen::Vector3d fa_, fb_;
};

// Ceres reports through glog what is not for the user's terminal: a failed Cholesky step that
// Levenberg-Marquardt recovers from, and, as an error, a solve ended because a residual could not
// be evaluated, which its Solver::Summary (read by every caller) says too. Only fatal messages
// are left. Called before every solve and evaluation; quiets once.
void QuietCeresLogs();

// Solves a problem of rotation costs (rotation averaging: a few unknowns, so solved to full
// convergence, on one thread for the same bits on every run).
void SolveRotationProblem(ceres::Problem& problem, int max_iterations);

// Residual of a relative rotation R_ab against R_b R_a^T as an angle-axis vector, scaled by the
// edge weight. Parameters: the rotations (4 each) of cam_a_from_rig and cam_b_from_rig.
struct RelativeRotationCost {
  RelativeRotationCost(const Eigen::Quaterniond& r_ab, double weight) : r_ab_inv_(r_ab.conjugate()), weight_(weight) {}

  template <typename T>
  bool operator()(const T* qa, const T* qb, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> ra(qa), rb(qb);
    const Eigen::Quaternion<T> e = r_ab_inv_.cast<T>() * rb * ra.conjugate();
    const T wxyz[4] = {e.w(), e.x(), e.y(), e.z()};
    ceres::QuaternionToAngleAxis(wxyz, residual);
    for (int i = 0; i < 3; ++i) residual[i] *= T(weight_);
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Quaterniond& r_ab, double weight) {
    return new ceres::AutoDiffCostFunction<RelativeRotationCost, 3, 4, 4>(new RelativeRotationCost(r_ab, weight));
  }

  Eigen::Quaterniond r_ab_inv_;
  double weight_;
};

// Residual of the relative rotation of two views, cam_b(t')_from_cam_a(t) = Q_b R_t' R_t^T Q_a^T,
// against its measurement as an angle-axis vector, scaled by the weight (rig_rotation_averaging.h).
// Parameters: Q_a, R_t, Q_b, R_t' (rotations, 4 each). ViewMotionRotationCost is the same for one
// camera's own motion (a = b): Q, R_t, R_t'.
struct ViewPairRotationCost {
  ViewPairRotationCost(const Eigen::Quaterniond& b_from_a, double weight) : inv_(b_from_a.conjugate()), weight_(weight) {}

  template <typename T>
  bool operator()(const T* qa, const T* rt, const T* qb, const T* rt2, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> a(qa), r(rt), b(qb), r2(rt2);
    return Residual(inv_.cast<T>() * b * r2 * r.conjugate() * a.conjugate(), weight_, residual);
  }

  template <typename T>
  static bool Residual(const Eigen::Quaternion<T>& e, double weight, T* residual) {
    const T wxyz[4] = {e.w(), e.x(), e.y(), e.z()};
    ceres::QuaternionToAngleAxis(wxyz, residual);
    for (int i = 0; i < 3; ++i) residual[i] *= T(weight);
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Quaterniond& b_from_a, double weight) {
    return new ceres::AutoDiffCostFunction<ViewPairRotationCost, 3, 4, 4, 4, 4>(new ViewPairRotationCost(b_from_a, weight));
  }

  Eigen::Quaterniond inv_;
  double weight_;
};

struct ViewMotionRotationCost {
  ViewMotionRotationCost(const Eigen::Quaterniond& b_from_a, double weight) : inv_(b_from_a.conjugate()), weight_(weight) {}

  template <typename T>
  bool operator()(const T* q, const T* rt, const T* rt2, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> c(q), r(rt), r2(rt2);
    return ViewPairRotationCost::Residual(inv_.cast<T>() * c * r2 * r.conjugate() * c.conjugate(), weight_, residual);
  }

  static ceres::CostFunction* Create(const Eigen::Quaterniond& b_from_a, double weight) {
    return new ceres::AutoDiffCostFunction<ViewMotionRotationCost, 3, 4, 4, 4>(new ViewMotionRotationCost(b_from_a, weight));
  }

  Eigen::Quaterniond inv_;
  double weight_;
};

// Holds a camera's centre in the rig along one axis at a given value (multi_frame_rig.h
// RigBundleAdjustmentOptions::held_centre_axis): weight * axis . (-R^T t - centre). Parameters:
// cam_from_rig rotation (4) and translation (3).
struct HeldCentreAxisCost {
  HeldCentreAxisCost(const Eigen::Vector3d& axis, double held, double weight) : axis_(axis), held_(held), weight_(weight) {}

  template <typename T>
  bool operator()(const T* q, const T* t, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> r(q);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> tr(t);
    const Eigen::Matrix<T, 3, 1> centre = -(r.conjugate() * tr);
    residual[0] = T(weight_) * (axis_.cast<T>().dot(centre) - T(held_));
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& axis, double held, double weight) {
    return new ceres::AutoDiffCostFunction<HeldCentreAxisCost, 1, 4, 3>(new HeldCentreAxisCost(axis, held, weight));
  }

  Eigen::Vector3d axis_;
  double held_;
  double weight_;
};

// Reprojection residual of one observation in the multi-frame rig bundle adjustment (pixels,
// projected minus observed): X_cam = cam_from_rig * (rig_from_world * X_world), through the
// camera model's ImgFromCam (geometry/camera_models.h). Parameters: cam_from_rig rotation (4) and
// translation (3), rig_from_world rotation (4) and translation (3), the point in the world (3),
// and the camera's intrinsics (its model's parameters, Camera::params()).
struct RigReprojectionCost {
  RigReprojectionCost(CameraModelId model, const Eigen::Vector2d& observed)
      : model(model), num_params(CameraModelNumParams(model)), observed(observed) {}

  // `P` is T when the intrinsics are differentiated, double when they are constants.
  template <typename T, typename P>
  bool Residual(const T* cam_q, const T* cam_t, const T* rig_q, const T* rig_t, const T* point, const P* intrinsics,
                T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> qc(cam_q), qr(rig_q);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> tc(cam_t), tr(rig_t), x(point);
    const Eigen::Matrix<T, 3, 1> x_in_cam = qc * (qr * x + tr) + tc;
    T params[kMaxParams];
    for (int i = 0; i < num_params; ++i) params[i] = T(intrinsics[i]);
    T px[2];
    if (!ImgFromCam(model, params, x_in_cam.data(), px)) return false;
    residual[0] = px[0] - T(observed.x());
    residual[1] = px[1] - T(observed.y());
    return true;
  }

  template <typename T>
  bool operator()(const T* cam_q, const T* cam_t, const T* rig_q, const T* rig_t, const T* point, const T* intrinsics,
                  T* residual) const {
    return Residual(cam_q, cam_t, rig_q, rig_t, point, intrinsics, residual);
  }

  static constexpr int kMaxParams = 12;  // the most any model has (FULL_OPENCV)
  CameraModelId model;
  int num_params;
  Eigen::Vector2d observed;
};

// The pose and point blocks of RigReprojectionCost only, the intrinsics constants copied in.
struct RigReprojectionHeldIntrinsics {
  RigReprojectionHeldIntrinsics(CameraModelId model, const double* values, const Eigen::Vector2d& observed)
      : cost(model, observed) {
    std::copy(values, values + cost.num_params, intrinsics);
  }
  template <typename T>
  bool operator()(const T* cam_q, const T* cam_t, const T* rig_q, const T* rig_t, const T* point, T* residual) const {
    return cost.Residual(cam_q, cam_t, rig_q, rig_t, point, intrinsics, residual);
  }
  RigReprojectionCost cost;
  double intrinsics[RigReprojectionCost::kMaxParams] = {};
};

// RigReprojectionCost with every parameter differentiated, the intrinsics included. Defined in
// cost_functions.cc for 4, 8 and 12 intrinsics, out of the callers' translation unit: instantiated
// beside the held path, its jets of 21-29 parameters keep GCC from inlining the held path's jet
// arithmetic, and the bundle adjustment runs 30% slower.
template <int kNumIntrinsics>
bool EvaluateRigReprojectionWithIntrinsics(const RigReprojectionCost& cost, double const* const* parameters,
                                           double* residuals, double** jacobians);

// The Ceres cost of RigReprojectionCost, with a parameter block of kNumIntrinsics for the
// intrinsics. While that block is held constant (Ceres then asks for no Jacobian of it) at the
// values the cost was made with, only the 17 pose and point parameters are differentiated, the
// intrinsics entering as constants: the arithmetic, and the speed, of a functor with the
// intrinsics copied in. Otherwise every parameter is differentiated: refining intrinsics needs
// nothing but SetParameterBlockVariable on their block.
template <int kNumIntrinsics>
class RigReprojectionCostFunction final : public ceres::SizedCostFunction<2, 4, 3, 4, 3, 3, kNumIntrinsics> {
 public:
  RigReprojectionCostFunction(CameraModelId model, const double* intrinsics, const Eigen::Vector2d& observed)
      : held_(new RigReprojectionHeldIntrinsics(model, intrinsics, observed)) {}

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const RigReprojectionHeldIntrinsics& held = held_.functor();
    const bool intrinsics_jacobian = jacobians != nullptr && jacobians[5] != nullptr;
    if (intrinsics_jacobian || !std::equal(parameters[5], parameters[5] + kNumIntrinsics, held.intrinsics)) {
      return EvaluateRigReprojectionWithIntrinsics<kNumIntrinsics>(held.cost, parameters, residuals, jacobians);
    }
    return held_.Evaluate(parameters, residuals, jacobians);  // reads the first five blocks only
  }

 private:
  ceres::AutoDiffCostFunction<RigReprojectionHeldIntrinsics, 2, 4, 3, 4, 3, 3> held_;
};

// Gaussian prior of one camera's intrinsics (intrinsics_refinement.h): residual i is
// weight_i (p_i - given_i), one per parameter, and one more, aspect_weight (fx - fy - (given fx -
// given fy)), tying the pixels' aspect ratio to the given one. Linear: the Jacobian is constant.
class IntrinsicsPriorCost final : public ceres::CostFunction {
 public:
  IntrinsicsPriorCost(std::vector<double> given, std::vector<double> weights, double aspect_weight)
      : given_(std::move(given)), weights_(std::move(weights)), aspect_weight_(aspect_weight) {
    set_num_residuals(static_cast<int>(given_.size()) + 1);
    mutable_parameter_block_sizes()->push_back(static_cast<int>(given_.size()));
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const int n = static_cast<int>(given_.size());
    const double* p = parameters[0];
    for (int i = 0; i < n; ++i) residuals[i] = weights_[i] * (p[i] - given_[i]);
    residuals[n] = aspect_weight_ * ((p[0] - p[1]) - (given_[0] - given_[1]));
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      double* j = jacobians[0];  // row-major (n + 1) x n
      std::fill(j, j + (n + 1) * n, 0.0);
      for (int i = 0; i < n; ++i) j[i * n + i] = weights_[i];
      j[n * n + 0] = aspect_weight_;
      j[n * n + 1] = -aspect_weight_;
    }
    return true;
  }

 private:
  std::vector<double> given_, weights_;
  double aspect_weight_;
};

// The cost of one observation of `camera`; its intrinsics block must have camera.params().size()
// entries. Throws std::invalid_argument for a model with another number of parameters.
// Reprojection residual of an observation whose camera captures between frames: the rig's pose at
// the capture time t_frame + offset + row_fraction * readout, interpolated between frames a and b
// (geometry/pose_interpolation.h) whose times are given relative to frame a's. Parameters:
// cam_from_rig rotation (4) and translation (3), rig_from_world of frame a (4, 3) and of frame b
// (4, 3), the camera's timing (offset, readout; seconds) and the point (3); the intrinsics are
// constants.
struct TimedRigReprojectionCost {
  TimedRigReprojectionCost(const Camera& camera, const Eigen::Vector2d& observed, double frame_time, double time_b,
                           double row_fraction)
      : cost(camera.model(), camera.params().data(), observed),
        frame_time(frame_time),
        time_b(time_b),
        row_fraction(row_fraction) {}

  template <typename T>
  bool operator()(const T* cam_q, const T* cam_t, const T* qa, const T* ta, const T* qb, const T* tb, const T* timing,
                  const T* point, T* residual) const {
    const T s = (T(frame_time) + timing[0] + T(row_fraction) * timing[1]) / T(time_b);
    Eigen::Quaternion<T> q;
    Eigen::Matrix<T, 3, 1> t;
    InterpolateRigFromWorld<T>(Eigen::Map<const Eigen::Quaternion<T>>(qa), Eigen::Map<const Eigen::Matrix<T, 3, 1>>(ta),
                               Eigen::Map<const Eigen::Quaternion<T>>(qb), Eigen::Map<const Eigen::Matrix<T, 3, 1>>(tb),
                               s, &q, &t);
    return cost(cam_q, cam_t, q.coeffs().data(), t.data(), point, residual);
  }

  static ceres::CostFunction* Create(const Camera& camera, const Eigen::Vector2d& observed, double frame_time,
                                     double time_b, double row_fraction) {
    return new ceres::AutoDiffCostFunction<TimedRigReprojectionCost, 2, 4, 3, 4, 3, 4, 3, 2, 3>(
        new TimedRigReprojectionCost(camera, observed, frame_time, time_b, row_fraction));
  }

  RigReprojectionHeldIntrinsics cost;
  double frame_time;    // the observation's frame, relative to frame a
  double time_b;        // frame b, relative to frame a
  double row_fraction;  // the observation's row over the image height, in readout order
};

inline ceres::CostFunction* CreateRigReprojectionCost(const Camera& camera, const Eigen::Vector2d& observed) {
  switch (camera.params().size()) {
    case 4: return new RigReprojectionCostFunction<4>(camera.model(), camera.params().data(), observed);
    case 8: return new RigReprojectionCostFunction<8>(camera.model(), camera.params().data(), observed);
    case 12: return new RigReprojectionCostFunction<12>(camera.model(), camera.params().data(), observed);
  }
  throw std::invalid_argument("CreateRigReprojectionCost: no cost for a camera with " +
                              std::to_string(camera.params().size()) + " parameters");
}

}  // namespace rigsim
