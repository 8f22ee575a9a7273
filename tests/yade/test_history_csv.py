"""The settling history as CSV: what a spreadsheet reads."""
import csv
import math

from viscbridge.scenes.history import write_history_csv


def test_energy_terms_not_yet_booked_are_zero_not_nan(tmp_path):
    data = {'t': [0.0, 1e-3], 'iter': [0, 5], 'dt': [1e-4, 1e-4], 'E_gravWork': [math.nan, -2e-11],
            'Ek': [0.0, 3e-11], 'liquidCoV': [math.nan, 0.5]}
    path = str(tmp_path / 'h.csv')
    write_history_csv(data, path)
    rows = list(csv.reader(open(path)))
    assert rows[0][:3] == ['dt', 'iter', 't']
    first = dict(zip(rows[0], rows[1]))
    assert float(first['E_gravWork']) == 0.0
    assert math.isnan(float(first['liquidCoV']))  # not an energy: nan stays what it means (no liquid yet)
