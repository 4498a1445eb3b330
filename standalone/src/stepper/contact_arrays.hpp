#pragma once
//! The engine's arrays as the contact resolver sees them (ContactResolver::bind).
#include <cstdint>

#include "hardsphere/state_exchange.hpp"
#include "hardsphere/transport.hpp"
#include "hardsphere/vec3.hpp"

namespace hardsphere {

//! Views of an engine's per-sphere arrays and of its neighbour lists (CSR, both directions).
//! For entry e = adj[k] of sphere s the separation is
//! pos[s] - pos[adj_partner(e)] - image_shift[adj_image(e)]; indices are at most kMaxAdjIndex.
template <class Real>
struct ContactArrays {
  Vec3<Real>* pos = nullptr;
  Vec3<Real>* vel = nullptr;
  const Real* radius = nullptr;
  const Real* mass = nullptr;
  const std::int64_t* id = nullptr;        //!< tie-break for equal contact times
  const std::uint32_t* id_slot = nullptr;  //!< if set, sphere i's id is id[id_slot[i]]
  const std::uint32_t* adj_start = nullptr;
  const std::uint32_t* adj = nullptr;       //!< adj_entry(partner, image), rows adj_start[s] .. adj_start[s + 1]
  const Vec3<Real>* image_shift = nullptr;  //!< 27 shifts by image code
  //! Optional: |vel| per sphere, current at the start of each step; the resolver keeps it
  //! current through collisions. Lets neighbour sweeps bound each pair's closing speed by
  //! |v_s| + |v_q| instead of |v_s| + the fastest speed of all.
  Real* speed = nullptr;
  //! Optional: row s's entries before adj_plain_end[s] all have image kNoImage (the sweeps then
  //! skip their shift, a sizeable part of the filter's instructions; see docs/dev/performance.md).
  const std::uint32_t* adj_plain_end = nullptr;
  //! Optional: each sphere's pair collisions (indexed like pos), incremented for both spheres.
  std::int64_t* pair_collisions = nullptr;
  //! Optional: 6 per sphere (indexed like pos): each collision adds half its virial tensor
  //! r_ij (x) dp_i (xx yy zz xy xz yz) to both spheres, so the spheres' sums add up to the tally's.
  double* sphere_virial = nullptr;
  //! Optional: told of every collision and bounce (indices like pos).
  CollisionObserver* observer = nullptr;
  //! Rough spheres (set_roughness): angular velocities, indexed like pos. nullptr: smooth, and
  //! collisions run the smooth kernel.
  Vec3<Real>* omega = nullptr;
  //! Kinematic spheres (1), indexed like pos; nullptr: none, and no collision asks.
  const std::uint8_t* kinematic = nullptr;
  //! Optional: the transport integrals, told of every pair collision (set_transport).
  TransportTally* transport = nullptr;
};

}  // namespace hardsphere
