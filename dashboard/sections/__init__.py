"""Reusable parts of the dashboard pages, one module per topic; each part is a function."""
