"""Module orders: parsing and refusal messages that name the position and the ID."""
import pytest

from modrob_build.errors import OrderError
from modrob_build.module_database import load_database
from modrob_build.order import parse_order, validate_order

SEED_3DOF = [59, 3, 55, 63, 57, 5]
SEED_6DOF = [59, 3, 55, 63, 64, 4, 66, 4, 67, 5, 56, 5]


@pytest.fixture(scope="module")
def db():
    return load_database()


@pytest.mark.parametrize("text", ["59,3,55,63,57,5", "[59, 3, 55, 63, 57, 5]", "59 3 55 63 57 5",
                                  SEED_3DOF, ["59", "3", "55", "63", "57", "5"]])
def test_parse_forms(text):
    assert parse_order(text) == SEED_3DOF


def test_seed_orders_are_valid(db):
    assert len(validate_order(SEED_3DOF, db)) == 6
    assert len(validate_order(SEED_6DOF, db)) == 12


@pytest.mark.parametrize("order,fragments", [
    ("59,3,x5,63", ["position 3", "'x5'", "integer"]),
    ("59,3,55.5", ["position 3", "'55.5'"]),
    ([59, 3, True], ["position 3"]),
])
def test_non_integer_named(order, fragments):
    with pytest.raises(OrderError) as err:
        parse_order(order)
    for f in fragments:
        assert f in str(err.value)


@pytest.mark.parametrize("order,fragments", [
    ([], ["empty"]),
    ([59, 3, 99, 63], ["position 3", "ID 99", "not in the module database"]),
    ([3, 59, 55, 63], ["position 1", "ID 3", "start with a base", "59"]),
    ([59, 3, 55, 59, 63], ["position 4", "ID 59", "second base"]),
    ([59, 3, 4, 5], ["no joint module"]),
    ([59], ["no joint module"]),
])
def test_invalid_orders_refused(db, order, fragments):
    with pytest.raises(OrderError) as err:
        validate_order(order, db)
    for f in fragments:
        assert f in str(err.value)
