#include "precomputed_response.h"

#include <stdexcept>

namespace tb {

PrecomputedResponse::PrecomputedResponse(const ElasticBody& body, std::vector<int> outputs)
    : body_(body),
      outputs_(std::move(outputs)),
      direct_(make_direct_solve(body)),
      slot_(static_cast<size_t>(body.mesh().V.rows()), -1) {
  for (int o : outputs_)
    if (o < 0 || o >= body.mesh().V.rows())
      throw std::invalid_argument("precomputed response: output node out of range");
}

void PrecomputedResponse::store_outputs(Columns& into, int c) const {
  for (Eigen::Index o = 0; o < into.rows(); ++o)
    into.block<1, 3>(o, 3 * c) = u_.segment<3>(3 * outputs_[static_cast<size_t>(o)]).transpose();
}

void PrecomputedResponse::precompute(const std::vector<int>& loaded_nodes) {
  const auto n_out = static_cast<Eigen::Index>(outputs_.size());
  for (int node : loaded_nodes) {
    if (node < 0 || node >= body_.mesh().V.rows())
      throw std::invalid_argument("precomputed response: loaded node out of range");
    if (slot_[static_cast<size_t>(node)] >= 0) continue;
    Columns block = Columns::Zero(n_out, 9);
    std::vector<int> rows;  // the node's free dofs: the unit force's nonzero rows
    for (int c = 0; c < 3; ++c)
      if (body_.free_index(3 * node + c) >= 0) rows.push_back(body_.free_index(3 * node + c));
    for (int c = 0; c < 3; ++c) {
      const int free = body_.free_index(3 * node + c);
      if (free < 0) continue;  // clamped: a force there moves nothing
      f_.setZero(body_.free_dofs());
      f_(free) = 1;
      u_.setZero(body_.dofs());
      direct_->solve(f_, &rows, u_);
      store_outputs(block, c);
    }
    slot_[static_cast<size_t>(node)] = static_cast<int>(columns_.size());
    columns_.push_back(std::move(block));
  }
}

void PrecomputedResponse::prepare(const BodyLoads& loads) {
  load_columns_.assign(loads.size(), Columns());
  for (size_t l = 0; l < loads.size(); ++l) {
    const NodalWeights& w = loads.load(l);
    if (w.size() <= kNodeColumnsUpTo) {
      std::vector<int> nodes;
      for (Eigen::Index k = 0; k < w.size(); ++k)
        if (w.weights(k) != 0) nodes.push_back(w.nodes(k));
      precompute(nodes);
      continue;
    }
    Columns& own = load_columns_[l];
    own = Columns::Zero(static_cast<Eigen::Index>(outputs_.size()), 9);
    std::vector<Eigen::Vector3d> unit(loads.size(), Eigen::Vector3d::Zero());
    for (int c = 0; c < 3; ++c) {
      unit[l] = Eigen::Vector3d::Unit(c);
      loads.assemble(unit, f_);
      u_.setZero(body_.dofs());
      direct_->solve(f_, nullptr, u_);
      store_outputs(own, c);
    }
  }
  prepared_ = &loads;
}

void PrecomputedResponse::apply(const BodyLoads& loads, const std::vector<Eigen::Vector3d>& values, Points& out) const {
  if (&loads != prepared_) throw std::logic_error("precomputed response: apply() with loads that were not prepared");
  const auto n_out = static_cast<Eigen::Index>(outputs_.size());
  if (out.rows() != n_out) out.resize(n_out, 3);
  out.setZero();
  // u_o = sum_c f_c (response of o to a unit force along c)
  const auto superpose = [&](const Columns& R, const Eigen::Vector3d& f) {
    for (Eigen::Index o = 0; o < n_out; ++o)
      out.row(o) += f(0) * R.block<1, 3>(o, 0) + f(1) * R.block<1, 3>(o, 3) + f(2) * R.block<1, 3>(o, 6);
  };
  for (size_t l = 0; l < loads.size(); ++l) {
    if (load_columns_[l].rows() > 0) {
      superpose(load_columns_[l], values[l]);
      continue;
    }
    const NodalWeights& w = loads.load(l);
    for (Eigen::Index k = 0; k < w.size(); ++k) {
      if (w.weights(k) == 0) continue;
      superpose(columns_[static_cast<size_t>(slot_[static_cast<size_t>(w.nodes(k))])], w.weights(k) * values[l]);
    }
  }
}

double PrecomputedResponse::memory_bytes() const {
  size_t blocks = columns_.size();
  for (const Columns& c : load_columns_) blocks += c.rows() > 0 ? 1 : 0;
  return static_cast<double>(blocks) * 9.0 * static_cast<double>(outputs_.size()) * sizeof(double);
}

}  // namespace tb
