"""The other papers' systems: scenarios, fusion, robust filtering, carrier tracking, latency."""
