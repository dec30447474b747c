"""Dynamics of the assembled (reduced) model beyond undamped modes: damping, frequency
response, Campbell diagrams and time integration. Each analysis here runs on the model
that :func:`assembly.model.assemble.assemble` returns and can state its error against the
unreduced (full-FE) model. Empty so far."""
