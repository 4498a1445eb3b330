#include "event/prediction.hpp"

namespace hardsphere::event {

Predictions::Predictions(const EventGeometry& geo, bool mono, const Trajectories& tr) : geo_(geo), mono_(mono) {
  const std::size_t n = tr.size();
  pred_.assign(n, Pred{kInf, kInf, kInf, 0, 0, 0, 0, 0, 0, 0});
  for (std::size_t k = 0; k < n; ++k) set_list_centre(int(k), tr[k].x, tr[k].y, tr[k].z);
  bnd_code_.assign(n, 0);
  count_.assign(n, 0);
}

std::vector<double> Predictions::next_times() const {
  std::vector<double> keys(pred_.size());
  for (std::size_t k = 0; k < pred_.size(); ++k) keys[k] = next_time(int(k));
  return keys;
}

void Predictions::shift_times(double shift) {
  for (Pred& p : pred_) {
    p.col_time -= shift;
    p.col2_time -= shift;
    p.bnd_time -= shift;
  }
}

void Predictions::permute(const Renumbering& r) {
  r.permute(pred_);
  r.permute(bnd_code_);
  r.permute(count_);
  for (Pred& p : pred_) {
    p.col_partner = r.new_of(std::size_t(p.col_partner));
    if (p.col2_partner >= 0) p.col2_partner = r.new_of(std::size_t(p.col2_partner));
  }
}

}  // namespace hardsphere::event
