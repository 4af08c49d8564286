"""From flat parameters (as the API and the CLI spell them) to a BRDF, through the model
registry (registry.py): ``model=`` names a family (family.py), each declared in its own
package — the microfacet model here (microfacet.py), the principled BRDF in
app/principled/, others in the directories of BRDF_MODEL_DIRS."""
from .family import Family
from .microfacet import (ALPHA2, ANISO_MAPS, ANISOTROPY, COMMON_NAMES, COMMON_PARAMS, KD, LOBE_MIX,
                         OPTIONAL_PARAMS, OPTIONS, ROUGHNESS, SUB_OPTIONS, AnisoMap, choice_param_names,
                         choice_params)
from .registry import (DEFAULT, ModelSpec, families, family_of, make_spec, query_fields,
                       refuse_method, refuse_view)

__all__ = ["ALPHA2", "ANISO_MAPS", "ANISOTROPY", "COMMON_NAMES", "COMMON_PARAMS", "DEFAULT", "KD",
           "LOBE_MIX", "OPTIONAL_PARAMS", "OPTIONS", "ROUGHNESS", "SUB_OPTIONS", "AnisoMap", "Family",
           "ModelSpec", "choice_param_names", "choice_params", "families", "family_of", "make_spec",
           "query_fields", "refuse_method", "refuse_view"]
