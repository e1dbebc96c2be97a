// The wave's work queues, in one place (as pbrt-v4's WorkQueue,
// wavefront/workqueue.h): one buffer of 3 x push.pathCount path slots, ray
// queue 0 (even bounces) | ray queue 1 (odd bounces) | the shadow queue,
// with their sizes in QueueCounters. The ray queues alternate by bounce
// parity: shade reads the queue of `bounce` and fills that of bounce + 1,
// which queue_dispatch emptied beforehand.
layout(binding = VKP_WF_QUEUES, scalar) buffer QueueBuffer { uint queues[]; };
layout(binding = VKP_WF_COUNTERS, scalar) buffer CounterBuffer { QueueCounters counters; };

bool oddBounce(uint bounce) { return (bounce & 1u) == 1u; }

uint rayQueueSize(uint bounce) { return oddBounce(bounce) ? counters.rayCount1 : counters.rayCount0; }

void setRayQueueSize(uint bounce, uint size) {
    if (oddBounce(bounce))
        counters.rayCount1 = size;
    else
        counters.rayCount0 = size;
}

uint rayQueueIndex(uint bounce, uint entry) { return (oddBounce(bounce) ? push.pathCount : 0u) + entry; }

// The path slot at `entry` of the ray queue of `bounce`.
uint rayQueueSlot(uint bounce, uint entry) { return queues[rayQueueIndex(bounce, entry)]; }

// Appends `slot` to the ray queue of `bounce`.
void pushRayQueue(uint bounce, uint slot) {
    uint entry = oddBounce(bounce) ? atomicAdd(counters.rayCount1, 1u) : atomicAdd(counters.rayCount0, 1u);
    queues[rayQueueIndex(bounce, entry)] = slot;
}

uint shadowQueueSize() { return counters.shadowCount; }

uint shadowQueueSlot(uint entry) { return queues[2u * push.pathCount + entry]; }

void pushShadowQueue(uint slot) { queues[2u * push.pathCount + atomicAdd(counters.shadowCount, 1u)] = slot; }
