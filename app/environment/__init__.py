"""A sphere lit by an environment map: the maps, the multiple-importance renderer and its figure."""
