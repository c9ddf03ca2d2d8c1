// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file erode_limits.h
/// What a job may ask of a generator (erode.h declares the checks both use: the memory cap, a
/// tolerance the coordinates resolve), and generator 2's up-front memory estimate, from the job alone, made
/// before anything large is built: the sweeps' facets dominate (each kept facet is carved, conformed and
/// emitted; every facet is culled). Fitted to the peak resident memory of the bundled and reproducer jobs
/// (tests/apps/erode_estimate_test.cpp holds it within a factor of 2).
#include <morph/erode.h>
#include <morph/erode2.h>
#include <morph/job.h>

namespace morph {

// Erode2Estimate and estimate_erode2() are public (erode2.h): `--generator auto` weighs them.

}  // namespace morph
