//! canopy's iceoryx2 service type: iceoryx2's `ipc::Service` with one
//! change, the wake-up event. iceoryx2's default event is a Unix datagram
//! socket: a sleeping reader costs its writer a `sendto`, and each sleep
//! five system calls (the socket switched to blocking and back, its
//! timeout set, a receive and a draining receive). Here it is a POSIX
//! semaphore in shared memory (a futex under glibc): a post is one atomic
//! add, and a system call only when someone sleeps on it; a sleep is one
//! `futex` wait. Beside other work, where nobody spins and every hand-off
//! between two participants is a wake-up (`presence.rs`), that is most of
//! what a hand-off costs (docs/src/exchange-speed.md).

use iceoryx2::service::Service;
use iceoryx2_bb_elementary_traits::testing::abandonable::Abandonable;
use iceoryx2_bb_elementary_traits::zero_copy_send::ZeroCopySend;
use iceoryx2_cal::shm_allocator::bump_allocator::BumpAllocator;
use iceoryx2_cal::shm_allocator::pool_allocator::PoolAllocator;
use iceoryx2_cal::*;
use std::fmt::Debug;

/// Every port of a canopy run: iceoryx2's `ipc::Service` but for
/// [`Service::Event`].
#[derive(Debug, Clone)]
pub struct Ipc {}

impl Service for Ipc {
    type StaticStorage = static_storage::recommended::Ipc;
    type ConfigSerializer = serialize::recommended::Recommended;
    type PersistentDynamicStorage<T: Debug + Send + Sync + ZeroCopySend + 'static> =
        dynamic_storage::recommended::PersistentIpc<T>;
    type Bag = bag::recommended::Recommended;
    type DynamicStorage<T: Debug + Send + Sync + ZeroCopySend + 'static> =
        dynamic_storage::recommended::Ipc<T>;
    type ServiceNameHasher = hash::recommended::Recommended;
    type SharedMemory = shared_memory::recommended::Ipc<PoolAllocator>;
    type ResizableSharedMemory = resizable_shared_memory::recommended::Ipc<PoolAllocator>;
    type Connection = zero_copy_connection::recommended::Ipc;
    /// The one change: a futex in shared memory, not a datagram socket.
    type Event = crate::futex_event::FutexEvent;
    type Monitoring = monitoring::recommended::Ipc;
    type Reactor = reactor::recommended::Ipc;
    type ArcThreadSafetyPolicy<T: Send + Debug + Abandonable> =
        arc_sync_policy::single_threaded::SingleThreaded<T>;
    type BlackboardMgmt<KeyType: Send + Sync + Debug + ZeroCopySend + 'static> =
        dynamic_storage::recommended::Ipc<KeyType>;
    type BlackboardPayload = shared_memory::recommended::Ipc<BumpAllocator>;
    type UniqueId = iceoryx2::unique_id_generator::unique_system_id::UniqueSystemId;
}

impl iceoryx2::service::internal::ServiceInternal<Ipc> for Ipc {}
