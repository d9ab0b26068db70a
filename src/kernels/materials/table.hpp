// The material table: one row per constitutive model, in the order of
// fdem::kernels::MaterialModelId and of the C enum FDEMMaterialModel
// (include/fdem/deformable.h). The kernel's dispatch table
// (MaterialModels(), src/kernels/cst.cpp) and the option names
// FDEMMaterialModels (src/model/deformable.cpp) are generated from it.
//
// A new material: write src/kernels/materials/<name>.hpp (a struct with kName,
// kSmallStrain, kCost, Stress and Energy, as the files below; tensor.hpp has
// shared pieces), include it here and add one ROW; see doc/architecture.md.
#pragma once
#include "munjiza_cst.hpp"
#include "neo_hookean.hpp"
#include "small_strain_linear.hpp"

#define FDEM_MATERIAL_TABLE(ROW) \
  ROW(MunjizaCST)                \
  ROW(NeoHookean)                \
  ROW(SmallStrainLinear)
