"""ADS for a running Runtime: TwinCAT's protocol, so pyads scripts, HMIs and SCADA talk to the simulated PLC.

``AdsServer(rt)`` serves the runtime's programs and global variable lists
under their TwinCAT symbol names (``MAIN.fbStation.nBottles``) on AMS port
851; the protocol is written with the standard library alone. The extra
``pip install "iecoop[ads]"`` installs pyads, the client the documentation's
scripts use. See docs/commissioning.md and docs/security.md.
"""

from iecoop.ads.protocol import AMS_TCP_PORT, AdsError, IndexGroup
from iecoop.ads.server import AdsServer

__all__ = ["AMS_TCP_PORT", "AdsError", "AdsServer", "IndexGroup"]
