#pragma once
/// Error of an image against a reference, over the R, G, B channels.
#include "engine/image.h"

namespace arbor::engine {

struct ImageError {
    double rmse = 0.0;     ///< sqrt(mean over pixels and channels of (x - ref)^2)
    double rel_mse = 0.0;  ///< mean of (x - ref)^2 / (ref^2 + 0.01): relative MSE, as in
                           ///< Rousselle et al. 2011, robust where the reference is dark
    double mean = 0.0;     ///< mean of x over pixels and channels
};

/// Compares channels R, G, B of `img` with those of `ref`. Throws InputError naming `ref_name`
/// when the sizes differ or a channel is missing.
ImageError compare_rgb(const Image& img, const Image& ref, const std::string& ref_name = "reference");

/// Mean of channels R, G, B.
double mean_rgb(const Image& img);

}  // namespace arbor::engine
