"""The allocation table: every live block of IEC memory, found by its handle.

A handle is what ``ADR`` returns and what a POINTER, REFERENCE or interface
variable stores: the allocation's number in the upper 32 bits, the byte
offset inside it in the lower 32. The runtime reads the table when an online
change retargets pointers into a replaced program, and when it frees the
blocks ``__NEW`` made.

ST: ``p := ADR(fbMotor);`` stores ``handle_of(motor)``; ``p^`` is
``resolve(p, SIZEOF(FB_Motor), 'p')``.

>>> from iecoop import INT, Struct
>>> from iecoop.memory.allocations import allocation_for_handle, handle_of, resolve
>>> class Point(Struct):
...     x: INT = 0
...     y: INT = 0
>>> point = Point()
>>> handle = handle_of(point, 2)            # ADR(point.y)
>>> block, offset = resolve(handle, 2, "p")
>>> block is point, offset
(True, 2)
>>> allocation_for_handle(handle) is not None
True
"""

# The table lives with the memory machinery it guards (one lock for both); this module is its public name.
from iecoop.memory._handles import Allocation, allocation_for_handle, free, handle_of, registered_allocation, resolve

__all__ = ["Allocation", "allocation_for_handle", "free", "handle_of", "registered_allocation", "resolve"]
