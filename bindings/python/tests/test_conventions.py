"""The package's Python conventions: one exception hierarchy, checked structs, flags that
numpy takes, one rule for ``out=``, rows of ids, names and docs, packaging."""

import pickle

import numpy as np
import pytest

import crowdgaze as cg

# --- errors ----------------------------------------------------------------------------------

#: Status -> (the class it raises, the built-in exceptions that class also is).
ERROR_CLASSES = {
    cg.Status.NULL_ARGUMENT: (cg.InvalidArgumentError, (ValueError,)),
    cg.Status.INVALID_ARGUMENT: (cg.InvalidArgumentError, (ValueError,)),
    cg.Status.NON_FINITE: (cg.NonFiniteError, (ValueError,)),
    cg.Status.NOT_FOUND: (cg.NotFoundError, (LookupError,)),
    cg.Status.CAPACITY: (cg.CapacityError, (RuntimeError,)),
    cg.Status.BAD_STRUCT_SIZE: (cg.InvalidArgumentError, (ValueError,)),
    cg.Status.WRONG_STATE: (cg.WrongStateError, (RuntimeError,)),
    cg.Status.NOT_CONVERGED: (cg.NotConvergedError, (RuntimeError,)),
    cg.Status.INTERNAL: (cg.InternalError, (RuntimeError,)),
    cg.Status.OUT_OF_MEMORY: (cg.OutOfMemoryError, (MemoryError,)),
    cg.Status.POISONED: (cg.InternalError, (RuntimeError,)),
}


def test_every_failing_status_has_its_error_class():
    assert set(ERROR_CLASSES) == set(cg.Status) - {cg.Status.OK}
    for status, (cls, builtins) in ERROR_CLASSES.items():
        error = cg.Error(status, "why", "cg_f")
        assert type(error) is cls, status
        assert isinstance(error, cg.Error) and isinstance(error, builtins), status
        assert (error.status, error.message, error.function) == (status, "why", "cg_f")
        assert str(error) == "cg_f: why"
        again = pickle.loads(pickle.dumps(error))
        assert type(again) is cls and again.status == status and str(again) == str(error)
    assert type(cg.Error(12345, "")) is cg.Error


def test_library_errors_are_the_matching_builtins():
    crowd = cg.Crowd(max_characters=1)
    me = crowd.add_character()
    with pytest.raises(LookupError) as info:
        crowd.remove_entity(1234)
    assert isinstance(info.value, cg.NotFoundError)
    assert info.value.function == "cg_crowd_remove_entity"
    with pytest.raises(ValueError) as info:
        crowd.step(float("nan"))
    assert isinstance(info.value, cg.NonFiniteError) and info.value.status == cg.Status.NON_FINITE
    with pytest.raises(ValueError) as info:
        crowd.step(-1.0)
    assert isinstance(info.value, cg.InvalidArgumentError)
    with pytest.raises(RuntimeError) as info:
        crowd.add_character()
    assert isinstance(info.value, cg.CapacityError)
    with pytest.raises(RuntimeError) as info:
        crowd.plan()
    assert isinstance(info.value, cg.WrongStateError)
    with pytest.raises(ValueError):
        cg.Crowd(max_characters=0)
    crowd.remove_entity(me)


def test_the_bindings_own_refusals_are_crowdgaze_errors_too():
    crowd = cg.Crowd(max_characters=1)
    cases = [
        (lambda: crowd.step("0.1"), cg.ArgumentTypeError, TypeError),
        (lambda: crowd.remove_entity(2**32), cg.ArgumentRangeError, OverflowError),
        (lambda: crowd.remove_entity(-1), cg.ArgumentRangeError, ValueError),
        (lambda: crowd.read_joints(out=np.zeros((3, 4))), cg.ArgumentTypeError, TypeError),
        (lambda: crowd.set_viewer((1, 2)), cg.InvalidArgumentError, ValueError),
    ]
    for call, cls, builtin in cases:
        with pytest.raises(cg.Error) as info:
            call()
        assert isinstance(info.value, cls) and isinstance(info.value, builtin), info.value
        assert info.value.function is None and info.value.message == str(info.value)
    crowd.close()
    with pytest.raises(cg.ClosedError) as info:
        crowd.step(0.1)
    assert isinstance(info.value, ValueError) and isinstance(info.value, cg.WrongStateError)
    assert info.value.status == cg.Status.WRONG_STATE
