#include "precomputed_response.h"

#include <algorithm>
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
  // Each group's response to a unit translation of its held components:
  // K_ff u_f = -K_fp u_p with u_p that translation (the other groups at rest).
  for (size_t g = 0; g < body.prescribed_groups().size(); ++g) {
    groups_.push_back(zero_response());
    for (int c = 0; c < 3; ++c) {
      if (!body.prescribed_groups()[g].components[c]) continue;
      unit_translation_response(body, *direct_, g, c, u_);
      f_full_.setZero(body.dofs());  // no external force: the reactions hold the translation alone
      store(groups_.back(), c);
    }
  }
}

PrecomputedResponse::Response PrecomputedResponse::zero_response() const {
  return {Columns::Zero(static_cast<Eigen::Index>(outputs_.size()), 9),
          Columns::Zero(static_cast<Eigen::Index>(body_.prescribed_groups().size() + 1), 9)};
}

void PrecomputedResponse::store(Response& into, int c) const {
  for (Eigen::Index o = 0; o < into.outputs.rows(); ++o)
    into.outputs.block<1, 3>(o, 3 * c) = u_.segment<3>(3 * outputs_[static_cast<size_t>(o)]).transpose();
  Eigen::Vector3d support;
  body_.reactions(u_, f_full_, group_work_, support);
  const Eigen::Index n_groups = into.reactions.rows() - 1;
  for (Eigen::Index g = 0; g < n_groups; ++g)
    into.reactions.block<1, 3>(g, 3 * c) = group_work_[static_cast<size_t>(g)].transpose();
  into.reactions.block<1, 3>(n_groups, 3 * c) = support.transpose();
}

void PrecomputedResponse::precompute(const std::vector<int>& loaded_nodes) {
  for (int node : loaded_nodes)
    if (node < 0 || node >= body_.mesh().V.rows())
      throw std::invalid_argument("precomputed response: loaded node out of range");
  // The nodes not yet computed, each once, in the order given (slot_ is set only
  // once a node's columns are stored, so a throw below leaves the rest to a retry).
  std::vector<int> todo;
  std::vector<char> queued(slot_.size(), 0);
  for (int node : loaded_nodes) {
    if (slot_[static_cast<size_t>(node)] >= 0 || queued[static_cast<size_t>(node)]) continue;
    queued[static_cast<size_t>(node)] = 1;
    todo.push_back(node);
  }
  // The unit forces of kBlockNodes nodes solved together (solve_columns reads the
  // factor once for all of them), then each column's outputs and reactions stored.
  constexpr size_t kBlockNodes = 32;
  Eigen::MatrixXd F, U;
  for (size_t begin = 0; begin < todo.size(); begin += kBlockNodes) {
    const size_t end = std::min(todo.size(), begin + kBlockNodes);
    F.setZero(body_.free_dofs(), static_cast<Eigen::Index>(3 * (end - begin)));
    for (size_t k = begin; k < end; ++k)
      for (int c = 0; c < 3; ++c) {
        const int free = body_.free_index(3 * todo[k] + c);
        if (free >= 0) F(free, static_cast<Eigen::Index>(3 * (k - begin)) + c) = 1;
      }
    direct_->solve_columns(F, U);
    for (size_t k = begin; k < end; ++k) {
      const int node = todo[k];
      Response block = zero_response();
      for (int c = 0; c < 3; ++c) {
        // On a clamped or held dof the force moves nothing: it is that dof's reaction.
        u_.setZero(body_.dofs());
        if (body_.free_index(3 * node + c) >= 0) body_.to_full(U.col(static_cast<Eigen::Index>(3 * (k - begin)) + c), u_);
        f_full_.setZero(body_.dofs());
        f_full_(3 * node + c) = 1;
        store(block, c);
      }
      slot_[static_cast<size_t>(node)] = static_cast<int>(columns_.size());
      columns_.push_back(std::move(block));
    }
  }
}

void PrecomputedResponse::prepare(const BodyLoads& loads) {
  load_columns_.assign(loads.size(), Response());
  for (size_t l = 0; l < loads.size(); ++l) {
    const NodalWeights& w = loads.load(l);
    if (w.size() <= kNodeColumnsUpTo) {
      std::vector<int> nodes;
      for (Eigen::Index k = 0; k < w.size(); ++k)
        if (w.weights(k) != 0) nodes.push_back(w.nodes(k));
      precompute(nodes);
      continue;
    }
    Response& own = load_columns_[l];
    own = zero_response();
    std::vector<Eigen::Vector3d> unit(loads.size(), Eigen::Vector3d::Zero());
    for (int c = 0; c < 3; ++c) {
      unit[l] = Eigen::Vector3d::Unit(c);
      loads.assemble(unit, f_);
      u_.setZero(body_.dofs());
      direct_->solve(f_, nullptr, u_);
      loads.assemble_full(unit, f_full_);
      store(own, c);
    }
  }
  prepared_ = &loads;
}

void PrecomputedResponse::apply(const BodyLoads& loads, const std::vector<Eigen::Vector3d>& values,
                                const std::vector<Eigen::Vector3d>& group_values, Points& out,
                                std::vector<Eigen::Vector3d>* reactions) const {
  if (&loads != prepared_) throw std::logic_error("precomputed response: apply() with loads that were not prepared");
  if (group_values.size() != groups_.size())
    throw std::logic_error("precomputed response: apply() with " + std::to_string(group_values.size()) +
                           " group values for " + std::to_string(groups_.size()) + " groups");
  const auto n_out = static_cast<Eigen::Index>(outputs_.size());
  if (out.rows() != n_out) out.resize(n_out, 3);
  out.setZero();
  if (reactions) reactions->assign(groups_.size() + 1, Eigen::Vector3d::Zero());
  // value_o = sum_c s_c (response of o to a unit source along c), for the outputs
  // and, when asked, the reactions.
  const auto superpose = [&](const Response& R, const Eigen::Vector3d& s) {
    for (Eigen::Index o = 0; o < n_out; ++o)
      out.row(o) += s(0) * R.outputs.block<1, 3>(o, 0) + s(1) * R.outputs.block<1, 3>(o, 3) +
                    s(2) * R.outputs.block<1, 3>(o, 6);
    if (!reactions) return;
    for (Eigen::Index r = 0; r < R.reactions.rows(); ++r)
      (*reactions)[static_cast<size_t>(r)] += (s(0) * R.reactions.block<1, 3>(r, 0) +
                                               s(1) * R.reactions.block<1, 3>(r, 3) +
                                               s(2) * R.reactions.block<1, 3>(r, 6)).transpose();
  };
  for (size_t l = 0; l < loads.size(); ++l) {
    if (load_columns_[l].outputs.rows() > 0) {
      superpose(load_columns_[l], values[l]);
      continue;
    }
    const NodalWeights& w = loads.load(l);
    for (Eigen::Index k = 0; k < w.size(); ++k) {
      if (w.weights(k) == 0) continue;
      superpose(columns_[static_cast<size_t>(slot_[static_cast<size_t>(w.nodes(k))])], w.weights(k) * values[l]);
    }
  }
  for (size_t g = 0; g < groups_.size(); ++g) superpose(groups_[g], group_values[g]);
}

double PrecomputedResponse::memory_bytes() const {
  size_t blocks = columns_.size() + groups_.size();
  for (const Response& c : load_columns_) blocks += c.outputs.rows() > 0 ? 1 : 0;
  const double per_block = 9.0 * static_cast<double>(outputs_.size() + groups_.size() + 1) * sizeof(double);
  return static_cast<double>(blocks) * per_block;
}

}  // namespace tb
