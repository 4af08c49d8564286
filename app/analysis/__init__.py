"""What the app measures about a model: the identities it must satisfy (checks), the
cheaper choices within a tolerance (advise), the cost/accuracy of each albedo method
(tradeoff). They measure; the integrals themselves live in ``app.integrate``."""
