"""Figure builders: functions that take results and return Plotly figures."""
