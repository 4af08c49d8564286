"""The lookup tables shaders ship (split sum, DFG, Kulla-Conty E): built on texel centres, quantised, exported and checked against an upload."""
