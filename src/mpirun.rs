//! The processes of a run under `mpirun`, through MPI (the `mpi` crate on the system's MPI
//! library): the core's [`Ranks`] implemented with MPI's collectives. A process not started by
//! a launcher never initialises MPI: a plain `blastsph run` runs as it always has.
//!
//! What the ranks share and what each computes is the core's business
//! ([`crate::modules::ranks`]): replicated data, partitioned row loops, gathered blocks.

use crate::modules::ranks::{self, Ranks};
use mpi::Threading;
use mpi::collective::SystemOperation;
use mpi::datatype::PartitionMut;
use mpi::environment::Universe;
use mpi::topology::{Communicator, SimpleCommunicator};
use mpi::traits::*;

/// The environment variables by which a launcher (Open MPI's, MPICH's or Slurm's through PMI)
/// tells a process that it is one of several.
const LAUNCHED: [&str; 4] = ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"];

/// The world communicator's ranks.
struct World {
    rank: usize,
    size: usize,
}

impl Ranks for World {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.size
    }

    fn allgather(&self, out: &mut [f64], counts: &[usize]) {
        let world = SimpleCommunicator::world();
        let mut displs = Vec::with_capacity(counts.len());
        let mut at = 0usize;
        for &c in counts {
            displs.push(at as i32);
            at += c;
        }
        let counts: Vec<i32> = counts.iter().map(|&c| c as i32).collect();
        let (lo, n) = (displs[self.rank] as usize, counts[self.rank] as usize);
        let mine = out[lo..lo + n].to_vec();
        let mut part = PartitionMut::new(&mut out[..at], &counts[..], &displs[..]);
        world.all_gather_varcount_into(&mine[..], &mut part);
    }

    fn any(&self, flag: bool) -> bool {
        let world = SimpleCommunicator::world();
        let mine = u32::from(flag);
        let mut all = 0u32;
        world.all_reduce_into(&mine, &mut all, SystemOperation::max());
        all != 0
    }

    fn broadcast(&self, bytes: &mut Vec<u8>) {
        let world = SimpleCommunicator::world();
        let root = world.process_at_rank(0);
        let mut len = bytes.len() as u64;
        root.broadcast_into(&mut len);
        bytes.resize(len as usize, 0);
        root.broadcast_into(&mut bytes[..]);
    }
}

/// MPI while it is up: dropping it finalises MPI (every rank must reach that point).
pub struct Session {
    _universe: Universe,
}

/// True when a launcher started this process as one of several.
pub fn launched() -> bool {
    LAUNCHED.iter().any(|v| std::env::var_os(v).is_some())
}

/// Starts MPI when a launcher started this process, and installs its ranks in the core. `None`
/// in a plain process (nothing is initialised), or when MPI cannot start.
pub fn start() -> Option<Session> {
    if !launched() {
        return None;
    }
    // the solver's stages call MPI from one thread at a time (a pool worker, not always the
    // same one)
    let (universe, _) = mpi::initialize_with_threading(Threading::Serialized)?;
    let world = universe.world();
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    ranks::install(Box::new(World { rank, size }));
    if rank > 0 {
        // rank 0 prints for the run; a legacy routine's own prints would repeat on every rank
        crate::os_ffi::silence_stdout();
    }
    Some(Session { _universe: universe })
}

/// Ends every rank at once with exit status `code` (a failure one rank saw alone: the others
/// would wait for it at their next collective).
pub fn abort(code: i32) -> ! {
    SimpleCommunicator::world().abort(code)
}

/// Worker threads a rank takes by default: the cores of its node shared among the node's ranks
/// (Open MPI and Slurm name how many ranks share the node).
pub fn default_threads() -> Option<usize> {
    if ranks::size() < 2 {
        return None;
    }
    let local = ["OMPI_COMM_WORLD_LOCAL_SIZE", "SLURM_NTASKS_PER_NODE", "MPI_LOCALNRANKS"]
        .iter()
        .find_map(|v| std::env::var(v).ok().and_then(|s| s.trim().parse::<usize>().ok()))
        .filter(|&n| n > 0)?;
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    Some((cores / local).max(1))
}
