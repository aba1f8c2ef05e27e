"""Signal filters: the alpha-beta-gamma filter, window selection, envelopes."""
