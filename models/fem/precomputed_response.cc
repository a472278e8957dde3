#include "precomputed_response.h"

#include <stdexcept>

namespace tb {

PrecomputedResponse::PrecomputedResponse(const ElasticBody& body, std::vector<int> outputs)
    : body_(body),
      outputs_(std::move(outputs)),
      direct_(make_elastic_solve("direct", body, {})),
      slot_(static_cast<size_t>(body.mesh().V.rows()), -1) {
  for (int o : outputs_)
    if (o < 0 || o >= body.mesh().V.rows())
      throw std::invalid_argument("precomputed response: output node out of range");
}

void PrecomputedResponse::precompute(const std::vector<int>& loaded_nodes) {
  const auto n_out = static_cast<Eigen::Index>(outputs_.size());
  for (int node : loaded_nodes) {
    if (node < 0 || node >= body_.mesh().V.rows())
      throw std::invalid_argument("precomputed response: loaded node out of range");
    if (slot_[static_cast<size_t>(node)] >= 0) continue;
    Eigen::Matrix<double, Eigen::Dynamic, 9, Eigen::RowMajor> block(n_out, 9);
    block.setZero();
    LoadStencil unit;
    unit.nodes.setConstant(node);
    unit.weights << 1, 0, 0, 0;
    for (int c = 0; c < 3; ++c) {
      if (body_.free_index(3 * node + c) < 0) continue;  // clamped: a force there moves nothing
      u_.setZero(body_.dofs());
      direct_->solve(unit, Eigen::Vector3d::Unit(c), u_);
      for (Eigen::Index o = 0; o < n_out; ++o)
        block.block<1, 3>(o, 3 * c) = u_.segment<3>(3 * outputs_[static_cast<size_t>(o)]).transpose();
    }
    slot_[static_cast<size_t>(node)] = static_cast<int>(columns_.size());
    columns_.push_back(std::move(block));
  }
}

void PrecomputedResponse::apply(const LoadStencil& load, const Eigen::Vector3d& force, Points& out) {
  for (int k = 0; k < 4; ++k)
    if (load.weights(k) != 0 && slot_[static_cast<size_t>(load.nodes(k))] < 0) precompute({load.nodes(k)});
  const auto n_out = static_cast<Eigen::Index>(outputs_.size());
  if (out.rows() != n_out) out.resize(n_out, 3);
  out.setZero();
  for (int k = 0; k < 4; ++k) {
    if (load.weights(k) == 0) continue;
    const auto& R = columns_[static_cast<size_t>(slot_[static_cast<size_t>(load.nodes(k))])];
    const Eigen::Vector3d f = load.weights(k) * force;
    // u_o = sum_c f_c (response of o to a unit force along c)
    for (Eigen::Index o = 0; o < n_out; ++o)
      out.row(o) += f(0) * R.block<1, 3>(o, 0) + f(1) * R.block<1, 3>(o, 3) + f(2) * R.block<1, 3>(o, 6);
  }
}

double PrecomputedResponse::memory_bytes() const {
  return static_cast<double>(columns_.size()) * 9.0 * static_cast<double>(outputs_.size()) * sizeof(double);
}

}  // namespace tb
