"""Fitting models of the registry to data sets: least squares over the free parameters,
standard errors from the Jacobian at the optimum, a time budget, and a ranking of every
NDF for one data set."""
