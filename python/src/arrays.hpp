#pragma once
//! numpy arrays over a ParticleSystem's vectors, read-only, with a base object that keeps the
//! memory alive for as long as any array does.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <string>

#include "hardsphere/particles.hpp"

namespace hardsphere::python {

//! positions, velocities (N, 3) float64; radii, masses (N,) float64; ids (N,) int64; types (N,)
//! int32; images (N, 3) int32; omegas (N, 3) float64.
enum class Field { Positions, Velocities, Radii, Masses, Ids, Types, Images, Omegas };

//! A read-only view of one field of `sys`; `owner` must keep `sys` alive.
pybind11::array view(const ParticleSystem& sys, Field f, pybind11::object owner);

//! An owner for views of a shared snapshot (a capsule holding a reference to it).
pybind11::object owner_of(std::shared_ptr<const ParticleSystem> s);

//! The field's docstring line (shape, dtype).
const char* describe(Field f);

}  // namespace hardsphere::python
