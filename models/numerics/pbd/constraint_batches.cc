#include "constraint_batches.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "batch_schedule.h"

namespace tb::pbd {

ConstraintBatches::ConstraintBatches(const ConstraintSet& c, const Eigen::VectorXd& w, int width, Precision precision,
                                     const std::vector<int>& vertex_domain)
    : width_(width), precision_(precision) {
  if (width != 4 && width != 8 && width != 16)
    throw std::invalid_argument("PBD constraint batches: 4, 8 or 16 lanes, not " + std::to_string(width));
  if (!vertex_domain.empty() && vertex_domain.size() != static_cast<size_t>(w.size()))
    throw std::invalid_argument("PBD constraint batches: one domain per vertex expected");
  const int domains = vertex_domain.empty() ? 0 : *std::max_element(vertex_domain.begin(), vertex_domain.end()) + 1;
  if (!vertex_domain.empty() && *std::min_element(vertex_domain.begin(), vertex_domain.end()) < 0)
    throw std::invalid_argument("PBD constraint batches: negative vertex domain");
  for (const KindConstraints& kind : c.kinds)
    kinds_.push_back(pack_kind(kind, w, width, precision, vertex_domain, domains));
}

const KindBatches& ConstraintBatches::of(const std::string& name) const {
  for (const KindBatches& k : kinds_)
    if (name == k.kind->name) return k;
  throw std::invalid_argument("PBD constraint batches: no kind '" + name + "'");
}

template <class S>
void ConstraintBatches::check(InstructionSet isa, const std::vector<double>& stiffness) const {
  const Precision p = precision_of<S>();
  if (!cpu_supports(isa)) throw std::invalid_argument(std::string("PBD sweep: this CPU has no ") + name(isa));
  if (p != precision_)
    throw std::invalid_argument(std::string("PBD sweep: ") + name(p) + " positions for batches packed in " +
                                name(precision_) + " precision");
  if (batch_width(isa, precision_) != width_)
    throw std::invalid_argument(std::string("PBD sweep: ") + name(isa) + " sweeps batches of " +
                                std::to_string(batch_width(isa, precision_)) + " lanes, these have " +
                                std::to_string(width_));
  if (stiffness.size() != kinds_.size())
    throw std::invalid_argument("PBD sweep: " + std::to_string(stiffness.size()) + " stiffnesses for " +
                                std::to_string(kinds_.size()) + " kinds of constraint");
}

template <class S>
void ConstraintBatches::sweep(S* positions, bool reverse, const std::vector<double>& stiffness,
                              const ProjectionOptions& options, InstructionSet isa,
                              std::vector<CorrectionRecord>* records) const {
  check<S>(isa, stiffness);
  run_sweeps(SweepPlan<S>{kinds_, stiffness, options, isa, positions, 1, reverse, nullptr, records});
}

template <class S>
void ConstraintBatches::project(S* positions, int iterations, const std::vector<double>& stiffness,
                                const ProjectionOptions& options, InstructionSet isa, ThreadTeam* team,
                                std::vector<CorrectionRecord>* records) const {
  check<S>(isa, stiffness);
  if (team && team->size() == 1) team = nullptr;
  run_sweeps(SweepPlan<S>{kinds_, stiffness, options, isa, positions, iterations, false, team, records});
}

std::vector<CorrectionRecord> ConstraintBatches::record_corrections(const ConstraintSet& constraints,
                                                                    const Eigen::VectorXd& inverse_mass,
                                                                    const std::vector<int>& group_of_vertex) const {
  if (group_of_vertex.size() != static_cast<size_t>(inverse_mass.size()))
    throw std::invalid_argument("PBD constraint batches: one group per vertex expected");
  std::vector<CorrectionRecord> records(kinds_.size());
  for (size_t k = 0; k < kinds_.size(); ++k) {
    const KindBatches& kind = kinds_[k];
    const KindConstraints& c = constraints.kinds[k];
    CorrectionRecord& r = records[k];
    r.arity = kind.kind->arity;
    r.of_row.assign(static_cast<size_t>(kind.rows), -1);
    r.batch_first.push_back(0);
    size_t next = 0;  // position in kind.order of the batch's lane 0
    for (size_t b = 0; b < kind.layout.batch_count(); ++b) {
      for (int l = 0; l < kind.layout.count[b]; ++l) {
        const int row = kind.order[next + static_cast<size_t>(l)];
        int group = -1;
        bool free = false;
        for (int j = 0; j < r.arity; ++j) {
          const int v = c.vertices(row, j);
          if (inverse_mass(v) > 0)
            free = true;
          else if (group < 0)
            group = group_of_vertex[static_cast<size_t>(v)];
        }
        if (group < 0 || !free) continue;
        r.of_row[static_cast<size_t>(row)] = static_cast<int>(r.row.size());
        r.row.push_back(row);
        r.group.push_back(group);
        r.lane.push_back(l);
        for (int j = 0; j < r.arity; ++j) {
          const double w = inverse_mass(c.vertices(row, j));
          r.mass.push_back(w > 0 ? 1 / w : 0);
        }
      }
      next += static_cast<size_t>(kind.layout.count[b]);
      r.batch_first.push_back(static_cast<int>(r.row.size()));
    }
    r.sum.assign(r.row.size(), Vec3::Zero());
  }
  return records;
}

template <class S>
void ConstraintBatches::corrections(const S* positions, const std::vector<double>& stiffness,
                                    const ProjectionOptions& options, InstructionSet isa,
                                    std::vector<Eigen::MatrixXd>& corrections) const {
  check<S>(isa, stiffness);
  corrections.resize(kinds_.size());
  for (size_t k = 0; k < kinds_.size(); ++k) {
    const KindBatches& kind = kinds_[k];
    corrections[k] = Eigen::MatrixXd::Zero(kind.rows, 3 * kind.kind->arity);
    kind.kind->kernels<S>().corrections[index(isa)](
        positions, KindSweep<S>{kind.layout, kind.numbers<S>(), stiffness[k], options}, kind.order, corrections[k]);
  }
}

// The API in both precisions (S = double or float), written once above.
#define TB_CONSTRAINT_BATCHES_API(S)                                                                           \
  template void ConstraintBatches::sweep(S*, bool, const std::vector<double>&, const ProjectionOptions&,       \
                                         InstructionSet, std::vector<CorrectionRecord>*) const;                \
  template void ConstraintBatches::project(S*, int, const std::vector<double>&, const ProjectionOptions&,      \
                                           InstructionSet, ThreadTeam*, std::vector<CorrectionRecord>*) const; \
  template void ConstraintBatches::corrections(const S*, const std::vector<double>&, const ProjectionOptions&, \
                                               InstructionSet, std::vector<Eigen::MatrixXd>&) const;
TB_CONSTRAINT_BATCHES_API(double)
TB_CONSTRAINT_BATCHES_API(float)
#undef TB_CONSTRAINT_BATCHES_API

}  // namespace tb::pbd
